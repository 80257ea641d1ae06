// tests/physics/mass_ratio_test.cpp: the promise on mass ratios (docs/dynamics.md, "Mass
// ratios"): stacks of unit boxes whose masses differ up to kStackMassRatio, heavy on light, stand
// at the default 10 iterations; past it the world warns, naming the bodies.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "support/physics_cases.h"
#include "support/test_util.h"

namespace rubble {
namespace {

std::string stack(const std::vector<double>& masses) {
    return test::massStackScene(masses);
}

void expectStackStands(const std::vector<double>& masses, float down, float sideways) {
    World world = test::worldFromText(stack(masses));
    test::expectStackStands(world, down, sideways);
}

// 100 kg on 1 kg. With Gauss-Seidel alone the light box passes the weight down by 1 % a sweep:
// it would sink into the floor, the pair tip and the heavy box fall off.
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
