// tests/physics/tumbling_test.cpp: a torque-free box with three distinct principal moments spun
// about its intermediate axis: angular momentum is conserved and the axis flips (Dzhanibekov).
#include <gtest/gtest.h>

#include "host/io/metrics.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// Half extents 0.5, 0.25, 0.1 give moments I_x < I_y < I_z: y is the intermediate axis. The body
// is turned 45 degrees about y, so world y is still its y axis; it spins mostly about y with a
// small wobble about x and z.
const char* kTumbling = R"({"format": "rubble-scene", "version": 1,
  "simulation": {"dt": 0.004166666666666667, "gravity": [0, 0, 0]},
  "shapes": {"brick": {"type": "box", "half_extents": [0.5, 0.25, 0.1]}},
  "bodies": [{"name": "brick", "shape": "brick", "mass": 3.0, "position": [0, 5, 0],
              "orientation": [0.9238795, 0.0, 0.3826834, 0.0],
              "angular_velocity": [0.01, 6.0, 0.01]}]})";

TEST(Tumbling, AngularMomentumIsConservedAndIntermediateAxisFlips) {
    World world = test::worldFromText(kTumbling);
    const glm::dvec3 l0(world.body(0).angularMomentum);
    const double e0 = measureInvariants(world).kineticEnergy;
    const glm::vec3 axis0 = world.body(0).orientation * glm::vec3(0, 1, 0);
    int flips = 0;
    float lastSign = 1.0f;
    double worstDrift = 0.0, worstEnergy = 0.0;
    for (int i = 0; i < 2400; ++i) { // 10 s at 240 Hz
        ASSERT_TRUE(world.step().ok());
        const BodyState b = world.body(0);
        worstDrift = std::max(worstDrift, glm::length(glm::dvec3(b.angularMomentum) - l0) / glm::length(l0));
        worstEnergy = std::max(worstEnergy, std::abs(measureInvariants(world).kineticEnergy / e0 - 1.0));
        // The body's y axis against its initial direction: the flip turns it around.
        const float along = glm::dot(b.orientation * glm::vec3(0, 1, 0), axis0);
        if (std::abs(along) > 0.9f && (along > 0.0f ? 1.0f : -1.0f) != lastSign) {
            ++flips;
            lastSign = -lastSign;
        }
    }
    EXPECT_LT(worstDrift, 1e-6);
    // The midpoint orientation update keeps the energy close (a first-order one doubles it).
    EXPECT_LT(worstEnergy, 1e-3);
    EXPECT_GE(flips, 2) << "the intermediate axis should turn over and back within 10 s";
}

TEST(Tumbling, SpinAboutMajorAxisIsStable) {
    std::string scene = kTumbling;
    // Angular velocity is in the world frame: start unrotated so that world z is the body's z.
    scene.replace(scene.find("[0.01, 6.0, 0.01]"), 17, "[0.01, 0.01, 6.0]");
    scene.replace(scene.find("[0.9238795, 0.0, 0.3826834, 0.0]"), 32, "[1, 0, 0, 0]");
    World world = test::worldFromText(scene);
    const glm::vec3 axis0 = world.body(0).orientation * glm::vec3(0, 0, 1);
    for (int i = 0; i < 2400; ++i) {
        ASSERT_TRUE(world.step().ok());
        EXPECT_GT(glm::dot(world.body(0).orientation * glm::vec3(0, 0, 1), axis0), 0.99f);
    }
}

} // namespace
} // namespace rubble
