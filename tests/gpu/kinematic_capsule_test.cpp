// tests/gpu/kinematic_capsule_test.cpp: kinematic bodies and capsules on the device's SAT + PGS
// path against the CPU reference: the capsule narrow phase on random pairs, platforms that carry,
// pushers that push, target poses, capsules resting and rolling at the analytic acceleration.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "gpu_fixture.h"
#include "host/collision/sat_collision.h"
#include "support/pair_cases.h"

namespace rubble {
namespace {

class KinematicCapsule : public test::GpuTest {
  protected:
    /// The scene of `json` on the device (SAT, PGS) and on the CPU.
    World device(const std::string& json) { return deviceWorld(json); }
    static World cpu(const std::string& json) { return test::worldFromText(json); }
};

// Whether the device's manifold is the CPU's: the same points and feature ids, normals within
// 1e-4, depths within 1e-5 m and positions within 1e-4 m.
std::string difference(const Manifold* cpu, const shared::ContactManifold& d) {
    const std::uint32_t count = cpu ? cpu->count : 0u;
    if (count != d.count)
        return "point count " + std::to_string(count) + " vs " + std::to_string(d.count);
    if (count == 0) return {};
    const glm::vec3 normal(d.normal.x, d.normal.y, d.normal.z);
    if (glm::length(normal - cpu->normal) > 1e-4f) return "normal differs";
    for (std::uint32_t i = 0; i < count; ++i) {
        const ContactPoint& p = cpu->points[i];
        const shared::float4 q = d.points[i];
        if (p.feature != d.features[i]) return "point " + std::to_string(i) + ": feature";
        if (std::fabs(p.depth - q.w) > 1e-5f) return "point " + std::to_string(i) + ": depth";
        if (glm::length(p.position - glm::vec3(q.x, q.y, q.z)) > 1e-4f)
            return "point " + std::to_string(i) + ": position";
    }
    return {};
}

// 3,000 random pairs with a capsule (against capsules, spheres, boxes, hulls and a plane): the
// device's capsule contacts (rubble/shared/capsule_contact.h) are the CPU's
// (host/collision/capsule_contact.cpp).
TEST_F(KinematicCapsule, CapsuleNarrowPhaseMatchesTheCpuOnRandomPairs) {
    test::PairCases cases = test::makeCapsuleCases(4101u, 3000);
    test::StageInput& in = cases.in;
    std::unique_ptr<test::DeviceStage> device = satStage(in);
    test::DeviceStage& p = *device;
    SatCollision cpu(ContactForm::Manifolds);
    const StepParams params = in.params();
    std::vector<BodyPair> pairs;
    for (std::uint32_t i = 0; i < cases.kinds.size(); ++i) pairs.push_back({2 * i, 2 * i + 1});
    StepContacts out;
    const Status found = cpu.broadPhase(in.collisionScene(), in.bodies.view(), params, out);
    ASSERT_TRUE(found.ok() || found.error().kind == ErrorKind::Limit) << found.error().describe();
    out.pairs = pairs;
    ASSERT_TRUE(cpu.narrowPhase(in.collisionScene(), in.bodies.view(), params, out).ok());
    ASSERT_TRUE(p.computeAabbs(params.dt).ok());
    ASSERT_TRUE(p.uploadPairs(pairs).ok());
    ASSERT_TRUE(p.narrowPhase(params.dt).ok());
    Result<std::vector<shared::ContactManifold>> manifolds = p.downloadManifolds();
    ASSERT_TRUE(manifolds.ok());
    ASSERT_EQ(manifolds->size(), pairs.size());
    std::size_t k = 0;
    int withContacts = 0, twoPoints = 0, mismatches = 0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const shared::ContactManifold& d = (*manifolds)[i];
        const Manifold* m = nullptr;
        if (k < out.manifolds.size() && out.manifolds[k].a == pairs[i].a &&
            out.manifolds[k].b == pairs[i].b)
            m = &out.manifolds[k++];
        withContacts += m != nullptr;
        twoPoints += m != nullptr && m->count == 2;
        const std::string why = difference(m, d);
        if (why.empty()) continue;
        if (++mismatches <= 10)
            ADD_FAILURE() << "pair " << i << " (" << test::toString(cases.kinds[i]) << ", shapes "
                          << in.bodies.shapeOf[pairs[i].a] << " and "
                          << in.bodies.shapeOf[pairs[i].b] << "): " << why;
    }
    std::printf("[ capsule narrow phase twin ] %zu pairs, %d with contacts, %d of two points, "
                "%d mismatched\n",
                pairs.size(), withContacts, twoPoints, mismatches);
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(withContacts, int(pairs.size()) / 2);
    EXPECT_GT(twoPoints, 100); // capsules lying on faces and planes, parallel capsules
}

// A 4 x 4 m platform, 0.2 m thick, moving along x at 1 m/s, with a crate resting on it that
// starts at the platform's speed.
std::string platformScene(const std::string& velocity = "[1, 0, 0]") {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "collision": {"method": "sat"}},
      "materials": {"default": {"friction": 0.6}},
      "shapes": {"deck": {"type": "box", "half_extents": [2, 0.1, 2]},
                 "crate": {"type": "box", "half_extents": [0.25, 0.25, 0.25]}},
      "bodies": [{"name": "platform", "shape": "deck", "kinematic": true,
                  "position": [0, 1, 0], "linear_velocity": )" +
           velocity + R"(},
                 {"name": "crate", "shape": "crate", "mass": 2, "position": [-1, 1.35, 0.3],
                  "linear_velocity": )" +
           velocity + "}]}";
}

TEST_F(KinematicCapsule, PlatformCarriesABoxWithoutSlip) {
    World d = device(platformScene()), c = cpu(platformScene());
    const std::uint32_t platform = *d.findBody("platform"), crate = *d.findBody("crate");
    ASSERT_TRUE(d.onDevice(crate));
    ASSERT_TRUE(test::stepWorld(d, 30));
    ASSERT_TRUE(test::stepWorld(c, 30));
    const glm::vec3 p0 = d.body(platform).position, c0 = d.body(crate).position;
    ASSERT_TRUE(test::stepWorld(d, 120)); // 2 s
    ASSERT_TRUE(test::stepWorld(c, 120));
    const glm::vec3 p1 = d.body(platform).position, c1 = d.body(crate).position;
    // The platform moves by its velocity alone, as on the CPU.
    EXPECT_NEAR(p1.x - p0.x, 2.0f, 1e-3f);
    EXPECT_EQ(p1.y, p0.y);
    EXPECT_EQ(p1, c.body(platform).position);
    const glm::vec3 slip = (c1 - c0) - (p1 - p0);
    EXPECT_LT(glm::length(slip), 1e-3f) << "slip " << slip.x << ", " << slip.y << ", " << slip.z;
    EXPECT_NEAR(d.body(crate).linearVelocity.x, 1.0f, 1e-3f);
    EXPECT_GT(c1.y, 1.35f - 0.01f) << "the crate sank into the platform";
    EXPECT_LT(glm::length(c1 - c.body(crate).position), 1e-3f) << "device and CPU apart";
    EXPECT_FALSE(d.body(platform).asleep);
    EXPECT_FALSE(d.body(crate).asleep);
}

// A platform at rest under a crate that fell asleep: a velocity set from the host starts both
// (the world at rest steps again), carries the crate, and a zero velocity lets it sleep again.
TEST_F(KinematicCapsule, VelocitySetFromTheHostMovesAPlatformAtRest) {
    World d = device(platformScene("[0, 0, 0]")), c = cpu(platformScene("[0, 0, 0]"));
    const std::uint32_t platform = *d.findBody("platform"), crate = *d.findBody("crate");
    ASSERT_TRUE(test::stepWorld(d, 120));
    ASSERT_TRUE(test::stepWorld(c, 120));
    ASSERT_TRUE(d.body(crate).asleep);
    const glm::vec3 p0 = d.body(platform).position, c0 = d.body(crate).position;
    for (World* w : {&d, &c})
        ASSERT_TRUE(w->setVelocity(platform, glm::vec3(0.0f, 0.0f, 0.5f), glm::vec3(0.0f)).ok());
    ASSERT_TRUE(test::stepWorld(d, 60)); // 1 s
    ASSERT_TRUE(test::stepWorld(c, 60));
    EXPECT_NEAR(d.body(platform).position.z - p0.z, 0.5f, 1e-3f);
    EXPECT_EQ(d.body(platform).position, c.body(platform).position);
    EXPECT_FALSE(d.body(crate).asleep);
    // Friction takes the crate along, as on the CPU.
    EXPECT_NEAR(d.body(crate).position.z - c0.z, 0.5f, 0.05f);
    EXPECT_LT(glm::length(d.body(crate).position - c.body(crate).position), 2e-3f);
    for (World* w : {&d, &c})
        ASSERT_TRUE(w->setVelocity(platform, glm::vec3(0.0f), glm::vec3(0.0f)).ok());
    ASSERT_TRUE(test::stepWorld(d, 120));
    const glm::vec3 stopped = d.body(platform).position;
    ASSERT_TRUE(test::stepWorld(d, 60));
    EXPECT_EQ(d.body(platform).position, stopped);
    EXPECT_TRUE(d.body(crate).asleep);
}

TEST_F(KinematicCapsule, SlowPlatformKeepsWhatItCarriesAwake) {
    // 1 cm/s is under the sleep speed: the platform's motion keeps the crate awake and along.
    World d = device(platformScene("[0.01, 0, 0]"));
    const std::uint32_t platform = *d.findBody("platform"), crate = *d.findBody("crate");
    ASSERT_TRUE(test::stepWorld(d, 30));
    const glm::vec3 p0 = d.body(platform).position, c0 = d.body(crate).position;
    ASSERT_TRUE(test::stepWorld(d, 180));
    EXPECT_FALSE(d.body(crate).asleep);
    const glm::vec3 slip = (d.body(crate).position - c0) - (d.body(platform).position - p0);
    EXPECT_LT(glm::length(slip), 1e-3f);
    EXPECT_NEAR(d.body(platform).position.x - p0.x, 0.03f, 1e-4f);
}

// Two crates asleep on the floor in a line before a blade moving at 1 m/s: it wakes them and
// pushes both ahead of it, as on the CPU.
TEST_F(KinematicCapsule, PusherWakesAndPushesBoxes) {
    const std::string scene = R"({"format": "rubble-scene", "version": 1,
      "simulation": {"collision": {"method": "sat"}},
      "materials": {"default": {"friction": 0.4}},
      "shapes": {"ground": {"type": "plane"},
                 "blade": {"type": "box", "half_extents": [0.1, 0.4, 1]},
                 "crate": {"type": "box", "half_extents": [0.25, 0.25, 0.25]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "pusher", "shape": "blade", "kinematic": true,
                  "position": [-1.35, 0.41, 0], "linear_velocity": [1, 0, 0]},
                 {"name": "near", "shape": "crate", "mass": 5, "position": [0, 0.25, 0]},
                 {"name": "far", "shape": "crate", "mass": 5, "position": [0.6, 0.25, 0.1]}]})";
    World d = device(scene), c = cpu(scene);
    const std::uint32_t pusher = *d.findBody("pusher"), near = *d.findBody("near"),
                        far = *d.findBody("far");
    ASSERT_TRUE(test::stepWorld(d, 54)); // 0.9 s: 0.1 m before the touch
    EXPECT_TRUE(d.body(near).asleep);
    EXPECT_NEAR(d.body(near).position.x, 0.0f, 1e-4f);
    ASSERT_TRUE(test::stepWorld(d, 126)); // to 3 s: pushed for 2 s
    ASSERT_TRUE(test::stepWorld(c, 180));
    const BodyState p = d.body(pusher), n = d.body(near), f = d.body(far);
    EXPECT_NEAR(p.position.x, -1.35f + 3.0f, 2e-3f);
    EXPECT_NEAR(p.position.y, 0.41f, 1e-6f);
    EXPECT_FALSE(n.asleep);
    EXPECT_FALSE(f.asleep);
    EXPECT_NEAR(n.position.x - p.position.x, 0.35f, 0.02f);
    EXPECT_NEAR(n.linearVelocity.x, 1.0f, 0.05f);
    EXPECT_GT(f.position.x, n.position.x + 0.49f) << "the far crate is pushed ahead of the near";
    EXPECT_NEAR(n.position.y, 0.25f, 0.01f);
    for (const std::uint32_t i : {near, far})
        EXPECT_LT(glm::length(d.body(i).position - c.body(i).position), 0.02f)
            << d.bodyName(i) << ": device and CPU apart";
}

TEST_F(KinematicCapsule, TargetPoseIsReachedEachStep) {
    World d = device(platformScene("[0, 0, 0]")), c = cpu(platformScene("[0, 0, 0]"));
    const std::uint32_t platform = *d.findBody("platform"), crate = *d.findBody("crate");
    ASSERT_TRUE(test::stepWorld(d, 30));
    ASSERT_TRUE(test::stepWorld(c, 30));
    auto onDeck = [&](const World& w) {
        const BodyState p = w.body(platform);
        return glm::conjugate(p.orientation) * (w.body(crate).position - p.position);
    };
    glm::vec3 settled(0.0f);
    // Slide 0.5 m along z over 1 s, turning 0.2 rad about y.
    for (int i = 1; i <= 60; ++i) {
        const float t = float(i) / 60.0f;
        const glm::vec3 target(0.0f, 1.0f, 0.5f * t);
        const glm::quat turn = glm::angleAxis(0.2f * t, glm::vec3(0, 1, 0));
        for (World* w : {&d, &c}) {
            ASSERT_TRUE(w->setKinematicTarget(platform, target, turn).ok());
            ASSERT_TRUE(w->step().ok());
        }
        EXPECT_EQ(d.body(platform).position, target);
        EXPECT_EQ(d.body(platform).position, c.body(platform).position);
        const glm::quat q = d.body(platform).orientation;
        EXPECT_LT(glm::length(glm::vec4(q.w - turn.w, q.x - turn.x, q.y - turn.y, q.z - turn.z)),
                  1e-6f);
        if (i == 15) settled = onDeck(d);
    }
    // The crate rides along on the device too, turning with the deck.
    EXPECT_LT(glm::length(onDeck(d) - settled), 2e-3f);
    const glm::vec3 arm = d.body(crate).position - d.body(platform).position;
    const glm::vec3 carried = glm::vec3(0.0f, 0.0f, 0.5f) + glm::cross(glm::vec3(0, 0.2f, 0), arm);
    EXPECT_LT(glm::length(d.body(crate).linearVelocity - carried), 0.01f);
    EXPECT_LT(glm::length(d.body(crate).position - c.body(crate).position), 2e-3f);
}

// Capsules dropped on a floor, on a box and on each other, a ball beside one, on both paths:
// the same rest.
TEST_F(KinematicCapsule, CapsulesRestOnFloorBoxAndEachOtherAsOnTheCpu) {
    const std::string scene = R"({"format": "rubble-scene", "version": 1,
      "simulation": {"collision": {"method": "sat"}},
      "shapes": {"ground": {"type": "plane"},
                 "table": {"type": "box", "half_extents": [1, 0.5, 1]},
                 "pill": {"type": "capsule", "radius": 0.15, "half_height": 0.3},
                 "ball": {"type": "sphere", "radius": 0.15}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "table", "shape": "table", "static": true, "position": [0, 0.5, 0]},
                 {"name": "onFloor", "shape": "pill", "mass": 1, "position": [2.5, 0.15, 0],
                  "orientation": [0.70710678, 0, 0, 0.70710678]},
                 {"name": "onBox", "shape": "pill", "mass": 1, "position": [0, 1.3, 0],
                  "orientation": [0.70710678, 0, 0, 0.70710678]},
                 {"name": "onPill", "shape": "pill", "mass": 1, "position": [0.05, 1.8, 0.02],
                  "orientation": [0.70710678, 0.70710678, 0, 0]},
                 {"name": "ball", "shape": "ball", "mass": 1, "position": [2.5, 0.15, 0.299]}]})";
    World d = device(scene), c = cpu(scene);
    ASSERT_TRUE(test::stepWorld(d, 240));
    ASSERT_TRUE(test::stepWorld(c, 240));
    EXPECT_NEAR(d.body(*d.findBody("onFloor")).position.y, 0.15f, 0.01f);
    EXPECT_NEAR(d.body(*d.findBody("onBox")).position.y, 1.15f, 0.01f);
    EXPECT_GT(d.body(*d.findBody("onPill")).position.y, 1.15f);
    EXPECT_LT(d.lastStep().largestPenetration, 0.01f);
    for (std::uint32_t i = 2; i < d.bodyCount(); ++i) {
        // Resting bodies end where the CPU's do.
        EXPECT_LT(glm::length(d.body(i).position - c.body(i).position), 0.02f) << d.bodyName(i);
        EXPECT_LT(glm::length(d.body(i).linearVelocity), 0.05f) << d.bodyName(i);
    }
}

// A capsule lying across a 30 degree incline (friction 0.6) rolls with g sin(theta) /
// (1 + I / (m r^2)), I its own inertia about its axis, within 2% on the device.
TEST_F(KinematicCapsule, CapsuleRollsDownAnInclineAtTheAnalyticAcceleration) {
    const float radius = 0.2f, mass = 3.0f, slope = 3.14159265f / 6.0f;
    const float nx = std::sin(slope), ny = std::cos(slope);
    const std::string scene =
        R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.004166667, "collision": {"method": "sat"}},
      "materials": {"default": {"friction": 0.6}},
      "shapes": {"slope": {"type": "plane", "normal": [)" +
        std::to_string(nx) + ", " + std::to_string(ny) + R"(, 0]},
                 "pill": {"type": "capsule", "radius": 0.2, "half_height": 0.4}},
      "bodies": [{"name": "slope", "shape": "slope", "static": true},
                 {"name": "pill", "shape": "pill", "mass": 3, "position": [)" +
        std::to_string(nx * radius) + ", " + std::to_string(ny * radius) +
        R"(, 0], "orientation": [0.70710678, 0.70710678, 0, 0]}]})";
    World d = device(scene);
    const std::uint32_t pill = *d.findBody("pill");
    const float axial = d.body(pill).inertia[1][1];
    const float expected = 9.81f * std::sin(slope) / (1.0f + axial / (mass * radius * radius));
    const glm::vec3 downhill(std::cos(slope), -std::sin(slope), 0.0f);
    ASSERT_TRUE(test::stepWorld(d, 24));
    const float v0 = glm::dot(d.body(pill).linearVelocity, downhill);
    const double t0 = d.time();
    ASSERT_TRUE(test::stepWorld(d, 240)); // 1 s
    const float v1 = glm::dot(d.body(pill).linearVelocity, downhill);
    const float measured = (v1 - v0) / float(d.time() - t0);
    EXPECT_NEAR(measured, expected, 0.02f * expected)
        << "measured " << measured << " m/s^2, analytic " << expected;
    EXPECT_NEAR(glm::length(d.body(pill).angularVelocity) * radius, v1, 0.02f * v1);
    const glm::vec3 axis = d.body(pill).orientation * glm::vec3(0, 1, 0);
    EXPECT_GT(std::abs(axis.z), 0.999f);
}

} // namespace
} // namespace rubble
