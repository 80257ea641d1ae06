// tests/physics/capsule_test.cpp: capsules on the CPU pipeline: rolling down an incline at the
// analytic acceleration, resting on one lying along it, resting on boxes and on each other.
#include <cmath>

#include <gtest/gtest.h>

#include "support/test_util.h"

namespace rubble {
namespace {

constexpr float kRadius = 0.2f, kHalfHeight = 0.4f, kMass = 3.0f;
constexpr float kSlope = 3.14159265f / 6.0f; // 30 degrees

// A plane rising along -x at 30 degrees (friction 0.6) and one capsule resting on it.
std::string inclineScene(const std::string& orientation) {
    const float nx = std::sin(kSlope), ny = std::cos(kSlope);
    return R"({"format": "rubble-scene", "version": 1, "simulation": {"dt": 0.004166667},
      "materials": {"default": {"friction": 0.6}},
      "shapes": {"slope": {"type": "plane", "normal": [)" + std::to_string(nx) + ", " +
           std::to_string(ny) + R"(, 0]},
                 "pill": {"type": "capsule", "radius": 0.2, "half_height": 0.4}},
      "bodies": [{"name": "slope", "shape": "slope", "static": true},
                 {"name": "pill", "shape": "pill", "mass": 3,
                  "position": [)" + std::to_string(nx * kRadius) + ", " +
           std::to_string(ny * kRadius) + R"(, 0], "orientation": )" + orientation + "}]}";
}

TEST(Capsule, RollsDownAnInclineAtTheAnalyticAcceleration) {
    // Lying across the slope: its axis (local y) along z.
    World w = test::worldFromText(inclineScene("[0.70710678, 0.70710678, 0, 0]"));
    const std::uint32_t pill = *w.findBody("pill");
    // I about its own axis, from the body's inertia (body frame y).
    const float axial = w.body(pill).inertia[1][1];
    const float g = 9.81f;
    const float expected = g * std::sin(kSlope) / (1.0f + axial / (kMass * kRadius * kRadius));
    const glm::vec3 downhill(std::cos(kSlope), -std::sin(kSlope), 0.0f);
    ASSERT_TRUE(test::stepWorld(w, 24)); // 0.1 s to settle the contact
    const float v0 = glm::dot(w.body(pill).linearVelocity, downhill);
    const double t0 = w.time();
    ASSERT_TRUE(test::stepWorld(w, 240)); // 1 s
    const float v1 = glm::dot(w.body(pill).linearVelocity, downhill);
    const float measured = (v1 - v0) / float(w.time() - t0);
    EXPECT_NEAR(measured, expected, 0.02f * expected)
        << "measured " << measured << " m/s^2, analytic " << expected;
    // Rolling, not sliding: the contact's speed is the centre's less the turn at the rim.
    const float spin = glm::length(w.body(pill).angularVelocity);
    EXPECT_NEAR(spin * kRadius, v1, 0.02f * v1);
    // Still along z and on the slope.
    const glm::vec3 axis = w.body(pill).orientation * glm::vec3(0, 1, 0);
    EXPECT_GT(std::abs(axis.z), 0.999f);
    const glm::vec3 n(std::sin(kSlope), std::cos(kSlope), 0.0f);
    EXPECT_NEAR(glm::dot(n, w.body(pill).position), kRadius, 0.005f);
}

TEST(Capsule, LyingAlongAnInclineStaysPut) {
    // Its axis along the slope's fall line: it cannot roll, and tan 30 < 0.6 holds it.
    World w = test::worldFromText(inclineScene("[0.8660254, 0, 0, 0.5]"));
    const std::uint32_t pill = *w.findBody("pill");
    ASSERT_TRUE(test::stepWorld(w, 24));
    const glm::vec3 p0 = w.body(pill).position;
    ASSERT_TRUE(test::stepWorld(w, 480)); // 2 s
    const glm::vec3 moved = w.body(pill).position - p0;
    EXPECT_LT(glm::length(moved), 0.005f)
        << "moved " << moved.x << ", " << moved.y << ", " << moved.z;
    EXPECT_LT(glm::length(w.body(pill).linearVelocity), 0.01f);
}

TEST(Capsule, PileOfCapsulesAndBoxesSettles) {
    // Capsules dropped on a static box and on each other, a box on top: they come to rest on
    // the box without sinking into it or each other.
    World w = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "shapes": {"table": {"type": "box", "half_extents": [2, 0.5, 2]},
                 "pill": {"type": "capsule", "radius": 0.15, "half_height": 0.3},
                 "crate": {"type": "box", "half_extents": [0.2, 0.2, 0.2]},
                 "ball": {"type": "sphere", "radius": 0.15}},
      "bodies": [{"name": "table", "shape": "table", "static": true},
                 {"name": "p0", "shape": "pill", "mass": 1, "position": [0, 0.8, 0],
                  "orientation": [0.70710678, 0, 0, 0.70710678]},
                 {"name": "p1", "shape": "pill", "mass": 1, "position": [0.05, 1.3, 0.02],
                  "orientation": [0.70710678, 0.70710678, 0, 0]},
                 {"name": "crate", "shape": "crate", "mass": 1, "position": [0.6, 0.9, 0.5]},
                 {"name": "ball", "shape": "ball", "mass": 1, "position": [-0.7, 0.9, -0.4]}]})");
    ASSERT_TRUE(test::stepWorld(w, 300));
    const BodyState p0 = w.body(*w.findBody("p0")), p1 = w.body(*w.findBody("p1"));
    // p0 lies on the table (top at 0.5), p1 across it or beside it, none sunk in.
    EXPECT_NEAR(p0.position.y, 0.5f + 0.15f, 0.01f);
    EXPECT_GT(p1.position.y, 0.5f + 0.15f - 0.01f);
    EXPECT_NEAR(w.body(*w.findBody("crate")).position.y, 0.7f, 0.01f);
    EXPECT_NEAR(w.body(*w.findBody("ball")).position.y, 0.65f, 0.01f);
    for (std::uint32_t i = 1; i < w.bodyCount(); ++i)
        EXPECT_LT(glm::length(w.body(i).linearVelocity), 0.05f) << w.bodyName(i);
    EXPECT_LT(w.lastStep().largestPenetration, 0.01f);
}

TEST(Capsule, DeviceParticlesAreRefusedNamingTheBody) {
    const Error e = test::sceneError(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"backend": "opencl", "collision": {"method": "particles"}},
      "shapes": {"pill": {"type": "capsule", "radius": 0.2, "half_height": 0.3}},
      "bodies": [{"name": "limb", "shape": "pill", "mass": 1}]})");
    EXPECT_EQ(e.kind, ErrorKind::NotSupported) << e.describe();
    EXPECT_NE(e.where.find("bodies[0].shape"), std::string::npos) << e.describe();
    EXPECT_NE(e.message.find("\"limb\""), std::string::npos) << e.describe();
}

TEST(Capsule, ParticlesVoxeliseIt) {
    // On the CPU's particle path a capsule is its voxels: it lands on the floor and stays.
    World w = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"collision": {"method": "particles", "particle_spacing": 0.05}},
      "shapes": {"ground": {"type": "plane"},
                 "pill": {"type": "capsule", "radius": 0.15, "half_height": 0.3}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "pill", "shape": "pill", "mass": 1, "position": [0, 0.5, 0],
                  "orientation": [0.70710678, 0, 0, 0.70710678]}]})");
    ASSERT_TRUE(test::stepWorld(w, 180));
    const BodyState p = w.body(1);
    EXPECT_NEAR(p.position.y, 0.15f, 0.04f);
    EXPECT_LT(glm::length(p.linearVelocity), 0.05f);
}

} // namespace
} // namespace rubble
