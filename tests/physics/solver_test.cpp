// tests/physics/solver_test.cpp: the solver options do what they say, warm starting lowers the
// residual, and the same scene gives the same bytes.
#include <cstring>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "physics/physics_util.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// Mean of the last sweep's residual over steps 10..59 of the stack of ten.
double stackResidual(bool warmStart, int iterations) {
    Scene scene = test::shippedScene("stack_10.json");
    scene.simulation.solver.warmStart = warmStart;
    scene.simulation.solver.iterations = iterations;
    World world = test::makeWorld(scene);
    double sum = 0.0;
    for (int step = 0; step < 60; ++step) {
        EXPECT_TRUE(test::stepWorld(world, 1));
        // Every sweep's residual is kept; the step reports the last.
        const std::span<const float> sweeps = world.solverResiduals();
        EXPECT_EQ(sweeps.size(), std::size_t(iterations));
        EXPECT_EQ(sweeps.back(), world.lastStep().solverResidual);
        if (step >= 10) sum += world.lastStep().solverResidual;
    }
    return sum / 50.0;
}

TEST(Solver, WarmStartingLowersTheStackResidual) {
    const double warm = stackResidual(true, 10), cold = stackResidual(false, 10);
    EXPECT_GT(cold, 0.0);
    EXPECT_LT(warm, 0.2 * cold) << "warm " << warm << " N s, cold " << cold << " N s";
}

TEST(Solver, MoreIterationsLowerTheResidual) {
    EXPECT_LT(stackResidual(false, 40), stackResidual(false, 5));
}

// A 1 kg box started 4 cm into the ground, at rest.
World sunkenBox(float baumgarte, float slop) {
    return test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"solver": {"baumgarte": )" +
                               std::to_string(baumgarte) + R"(, "slop": )" + std::to_string(slop) +
                               R"(}},
      "shapes": {"ground": {"type": "plane"}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "box", "shape": "crate", "mass": 1, "position": [0, 0.46, 0]}]})");
}

TEST(Solver, BaumgartePushesPenetrationOutDownToTheSlop) {
    World pushed = sunkenBox(0.2f, 0.005f);
    EXPECT_TRUE(test::stepWorld(pushed, 120));
    EXPECT_NEAR(pushed.body(1).position.y, 0.5f - 0.005f, 0.002f);
    // The push moves the box but gives it no speed: it does not fly off.
    EXPECT_LT(glm::length(pushed.body(1).linearVelocity), 0.01f);
    World kept = sunkenBox(0.0f, 0.005f);
    EXPECT_TRUE(test::stepWorld(kept, 120));
    EXPECT_NEAR(kept.body(1).position.y, 0.46f, 0.002f);
    World slack = sunkenBox(0.2f, 0.05f);
    EXPECT_TRUE(test::stepWorld(slack, 120));
    EXPECT_NEAR(slack.body(1).position.y, 0.46f, 0.002f);
}

TEST(Solver, RelaxationScalesTheFirstSweep) {
    // One cold sweep over a single box landing flat: relaxation w scales its first impulses.
    auto firstSweep = [](float w) {
        World world = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
          "simulation": {"solver": {"iterations": 1, "relaxation": )" +
                                          std::to_string(w) + R"(}},
          "shapes": {"ground": {"type": "plane"}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
          "bodies": [{"name": "floor", "shape": "ground", "static": true},
                     {"name": "box", "shape": "crate", "mass": 1, "position": [0, 0.499, 0],
                      "linear_velocity": [0, -1, 0]}]})");
        EXPECT_TRUE(test::stepWorld(world, 1));
        return world.lastStep().solverResidual;
    };
    const float full = firstSweep(1.0f), half = firstSweep(0.5f);
    EXPECT_GT(full, 0.0f);
    // Not exactly a half: the friction rows' clamps do not scale.
    EXPECT_NEAR(half / full, 0.5f, 0.03f);
}

// Every body's pose, velocities, momenta and sleep, as bytes.
std::vector<unsigned char> stateBytes(const World& world) {
    std::vector<unsigned char> bytes;
    auto append = [&](const auto& v) {
        const auto* c = reinterpret_cast<const unsigned char*>(&v);
        bytes.insert(bytes.end(), c, c + sizeof v);
    };
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        append(b.position);
        append(b.orientation);
        append(b.linearVelocity);
        append(b.angularVelocity);
        append(b.linearMomentum);
        append(b.angularMomentum);
        append(b.asleep);
    }
    return bytes;
}

void expectSameBytes(const std::string& file, int steps) {
    const Scene scene = test::shippedScene(file);
    World first = test::makeWorld(scene), second = test::makeWorld(scene);
    for (int step = 0; step < steps; ++step) {
        ASSERT_TRUE(test::stepWorld(first, 1));
        ASSERT_TRUE(test::stepWorld(second, 1));
        ASSERT_EQ(stateBytes(first), stateBytes(second)) << file << " differs at step " << step;
    }
}

TEST(Solver, SameSceneSameBytes) {
    expectSameBytes("ragdoll.json", 200); // joints, contacts, sleeping
    expectSameBytes("pyramid_20.json", 60);
}

} // namespace
} // namespace rubble
