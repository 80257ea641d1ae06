// tests/physics/mass_ratio_test.cpp: the promise on mass ratios (docs/dynamics.md, "Mass
// ratios"): stacks of unit boxes whose masses differ up to kStackMassRatio, heavy on light, stand
// at the default 10 iterations; past it the world warns, naming the bodies.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "support/test_util.h"

namespace rubble {
namespace {

// Unit boxes stacked on a floor (friction 0.5), box i of mass masses[i] with its centre at
// i + 0.5 m, the resting height; 60 Hz, 10 iterations (the defaults).
std::string stack(const std::vector<double>& masses) {
    std::string bodies = R"({"name": "floor", "shape": "ground", "static": true})";
    for (std::size_t i = 0; i < masses.size(); ++i) {
        char body[160];
        std::snprintf(
            body, sizeof body,
            R"(, {"name": "b%zu", "shape": "crate", "mass": %.9g, "position": [0, %g, 0]})", i,
            masses[i], double(i) + 0.5);
        bodies += body;
    }
    return R"({"format": "rubble-scene", "version": 1,
      "shapes": {"ground": {"type": "plane"}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [)" +
           bodies + "]}";
}

// For 10 s every box stays within `down` of its resting height (i + 0.5 m) and `sideways` of
// the axis it started on, and then the whole stack sleeps.
void expectStackStands(const std::vector<double>& masses, float down, float sideways) {
    World world = test::worldFromText(stack(masses));
    ASSERT_EQ(world.options().solver.iterations, 10);
    float worstDown = 0.0f, worstSideways = 0.0f;
    for (int step = 0; step < 600; ++step) {
        ASSERT_TRUE(world.step().ok());
        for (std::uint32_t i = 1; i < world.bodyCount(); ++i) {
            const glm::vec3 p = world.body(i).position;
            worstDown = std::max(worstDown, float(i) - 0.5f - p.y);
            worstSideways = std::max(worstSideways, std::hypot(p.x, p.z));
        }
    }
    EXPECT_LT(worstDown, down) << "m below the resting heights";
    EXPECT_LT(worstSideways, sideways) << "m off the stack's axis";
    for (std::uint32_t i = 1; i < world.bodyCount(); ++i)
        EXPECT_TRUE(world.body(i).asleep) << world.bodyName(i) << " settles";
}

// 100 kg on 1 kg. With Gauss-Seidel alone the light box passes the weight down by 1 % a sweep:
// it sank 4 cm into the floor, the pair tipped and the heavy box fell off (1 m below its height).
TEST(MassRatio, HeavyBoxOnALightOneStandsAtTheStatedRatio) {
    ASSERT_EQ(kStackMassRatio, 100.0f);
    expectStackStands({1.0, 100.0}, 0.01f, 0.05f);
}

// 100 kg on two 1 kg boxes: the middle one carries the load, and so does the bottom one.
TEST(MassRatio, HeavyBoxOnTwoLightOnesStands) {
    expectStackStands({1.0, 1.0, 100.0}, 0.01f, 0.08f);
}

// Equal masses (no pass) and 1:10 stand as before, closer still.
TEST(MassRatio, SmallerRatiosStand) {
    expectStackStands({1.0, 1.0}, 0.001f, 0.005f);
    expectStackStands({1.0, 10.0}, 0.002f, 0.005f);
}

// Past the ratio the world is built and runs, and says so, naming both bodies and the ratio.
TEST(MassRatio, PastTheRatioTheWorldWarnsNamingTheBodies) {
    World at = test::worldFromText(stack({1.0, 100.0}));
    EXPECT_TRUE(at.warnings().empty()) << "1:100 is within the promise";
    World past = test::worldFromText(stack({1e-9, 1.0, 1e9}));
    ASSERT_EQ(past.warnings().size(), 1u);
    const Warning& w = past.warnings()[0];
    EXPECT_EQ(w.where, "inline.json: bodies[1] and bodies[3]");
    EXPECT_NE(w.message.find("b0 (1e-09 kg) and b2 (1e+09 kg) differ 1:1e+18"), std::string::npos)
        << w.message;
    EXPECT_NE(w.message.find("stacks stand up to 1:100"), std::string::npos) << w.message;
    ASSERT_TRUE(past.step().ok());
}

} // namespace
} // namespace rubble
