// tests/physics/sleep_test.cpp: islands fall asleep when still, cost nothing while asleep, and
// wake when touched or pushed through the API.
#include <gtest/gtest.h>

#include "physics/physics_util.h"
#include "support/physics_cases.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// A stack of three 1 m boxes and, 4 m to the side, a ball that can be dropped on it later.
const char* kStack = R"({"format": "rubble-scene", "version": 1,
  "shapes": {"ground": {"type": "plane"}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
             "ball": {"type": "sphere", "radius": 0.3}},
  "bodies": [{"name": "floor", "shape": "ground", "static": true},
             {"name": "b0", "shape": "crate", "mass": 1, "position": [0, 0.5, 0]},
             {"name": "b1", "shape": "crate", "mass": 1, "position": [0, 1.5, 0]},
             {"name": "b2", "shape": "crate", "mass": 1, "position": [0, 2.5, 0]},
             {"name": "ball", "shape": "ball", "mass": 5, "position": [4, 0.3, 0]}]})";

bool allAsleep(const World& w, std::uint32_t first, std::uint32_t last) {
    for (std::uint32_t i = first; i <= last; ++i)
        if (!w.body(i).asleep) return false;
    return true;
}
bool noneAsleep(const World& w, std::uint32_t first, std::uint32_t last) {
    for (std::uint32_t i = first; i <= last; ++i)
        if (w.body(i).asleep) return false;
    return true;
}

TEST(Sleep, StillIslandSleepsAfterHalfASecondAndCostsNothing) {
    World world = test::worldFromText(kStack);
    ASSERT_TRUE(test::stepWorld(world, 25)); // 0.42 s: not yet
    EXPECT_TRUE(noneAsleep(world, 1, 3));
    ASSERT_TRUE(test::stepWorld(world, 95));
    ASSERT_TRUE(allAsleep(world, 1, 4));
    // Asleep: zero velocities and momenta, no rows, no pairs.
    for (std::uint32_t i = 1; i <= 4; ++i) {
        EXPECT_EQ(world.body(i).linearVelocity, glm::vec3(0.0f));
        EXPECT_EQ(world.body(i).angularMomentum, glm::vec3(0.0f));
    }
    const glm::vec3 before = world.body(3).position;
    ASSERT_TRUE(test::stepWorld(world, 60));
    EXPECT_EQ(world.body(3).position, before);
    EXPECT_EQ(world.lastStep().pairCount, 0u);
    EXPECT_EQ(world.lastStep().contactCount, 0u);
    EXPECT_TRUE(world.contacts().empty());
}

// simulation.sleep false: the same stack settles as it does with sleep, and stays awake, its
// contacts collided and solved every step; the stack of the test above is asleep by then.
TEST(Sleep, SleepFalseKeepsASettledStackAwake) {
    std::string text = kStack;
    text.insert(text.find("\"shapes\""), R"("simulation": {"sleep": false}, )");
    World awake = test::worldFromText(text);
    World sleeping = test::worldFromText(kStack);
    ASSERT_TRUE(test::stepWorld(awake, 180));
    ASSERT_TRUE(test::stepWorld(sleeping, 180));
    EXPECT_TRUE(allAsleep(sleeping, 1, 4));
    EXPECT_TRUE(noneAsleep(awake, 1, 4));
    EXPECT_EQ(awake.lastStep().asleep, 0u);
    EXPECT_GE(awake.lastStep().contactCount, 12u) << "three box faces of 4 points each";
    for (std::uint32_t i = 1; i <= 3; ++i) {
        // Settled: slow, and where it started (a box's centre 0.5 m above the one below).
        EXPECT_LT(glm::length(awake.body(i).linearVelocity), 0.05f) << awake.bodyName(i);
        EXPECT_NEAR(awake.body(i).position.y, float(i) - 0.5f, 0.02f) << awake.bodyName(i);
        EXPECT_NEAR(awake.body(i).position.x, 0.0f, 0.01f) << awake.bodyName(i);
    }
}

TEST(Sleep, PushThroughTheApiWakesTheWholeIsland) {
    World world = test::worldFromText(kStack);
    ASSERT_TRUE(test::stepWorld(world, 120));
    ASSERT_TRUE(allAsleep(world, 1, 3));
    world.applyImpulse(3, glm::vec3(0.5f, 0.0f, 0.0f), world.body(3).position);
    EXPECT_FALSE(world.body(3).asleep);
    ASSERT_TRUE(test::stepWorld(world, 1));
    EXPECT_TRUE(noneAsleep(world, 1, 3)) << "the top box's island wakes with it";
    EXPECT_GT(world.body(3).linearVelocity.x, 0.0f);
    ASSERT_TRUE(test::stepWorld(world, 300));
    EXPECT_TRUE(allAsleep(world, 1, 3)) << "and sleeps again once still";
    EXPECT_GT(world.body(3).position.x, 0.01f);
}

TEST(Sleep, AwakeBodyTouchingASleepingIslandWakesIt) {
    World world = test::worldFromText(kStack);
    ASSERT_TRUE(test::stepWorld(world, 120));
    ASSERT_TRUE(allAsleep(world, 1, 4));
    // Roll the ball into the bottom box.
    world.applyImpulse(4, glm::vec3(-20.0f, 0.0f, 0.0f), world.body(4).position);
    bool woke = false;
    for (int step = 0; step < 120 && !woke; ++step) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        woke = noneAsleep(world, 1, 3);
    }
    EXPECT_TRUE(woke) << "the ball's hit wakes the stack";
}

// A body hit while asleep wakes before the solve of that step, with its island, and its mass
// takes part in that solve (tests/support/physics_cases.h).
TEST(Sleep, SleepingRowTakesTheHitWithItsMomentum) {
    World world = test::worldFromText(test::sleepingRowScene());
    test::expectSleepingRowTakesTheHit(world, 1e-3);
}
// The same row with its boxes resting against each other: the island wakes as one, so the hit
// moves all five, not the first against four walls.
TEST(Sleep, TouchingSleepingRowTakesTheHitWithItsMomentum) {
    World world = test::worldFromText(test::sleepingRowScene("", 0.0));
    test::expectSleepingRowTakesTheHit(world, 1e-3);
    EXPECT_GT(world.body(6).position.x, 4.0f + 0.1f) << "the last box of the row moves";
}
// A column that topples slowly is one island with its moving top: its base, slower than the
// sleep speeds for the first second, stays awake and is dragged along as the column falls,
// instead of sleeping under it as a fixed pivot.
TEST(Sleep, BaseOfASlowlyTopplingColumnStaysAwake) {
    World world = test::worldFromText(test::leaningColumnScene());
    const float topStart = world.body(16).position.x;
    for (int step = 0; step < 180; ++step) {
        ASSERT_TRUE(world.step().ok());
        for (std::uint32_t i = 1; i < world.bodyCount(); ++i)
            ASSERT_FALSE(world.body(i).asleep) << world.bodyName(i) << " at step " << step;
    }
    EXPECT_GT(world.body(16).position.x - topStart, 2.0f) << "m the top has moved: it topples";
    EXPECT_GT(glm::length(world.body(1).linearVelocity), 1e-3f) << "m/s: the base moves with it";
}
TEST(Sleep, TouchingRowWithAJointTakesTheHitWithItsMomentum) {
    World world = test::worldFromText(test::jointedRowScene());
    test::expectSleepingRowTakesTheHit(world, 1e-3);
    EXPECT_GT(world.body(6).position.x, 4.0f + 0.1f) << "the last box of the row moves";
}
TEST(Sleep, ElasticBallHittingASleepingOneStopsAndPassesItsVelocityOn) {
    World world = test::worldFromText(test::cradleScene());
    test::expectCradleExchange(world, 1e-3f);
}
TEST(Sleep, ExplosionIntoASleepingRowKeepsItsMomentum) {
    World world = test::worldFromText(test::explodedRowScene());
    test::expectExplodedRowKeepsItsMomentum(world, 1e-3);
}

TEST(Sleep, FallingBodyIsNotPutToSleepAtItsApex) {
    // Thrown straight up at 0.2 m/s: slow for a moment at the top, but not for half a second.
    World world = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "shapes": {"ball": {"type": "sphere", "radius": 0.1}},
      "bodies": [{"name": "ball", "shape": "ball", "mass": 1, "position": [0, 10, 0],
                  "linear_velocity": [0, 0.2, 0]}]})");
    for (int step = 0; step < 120; ++step) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        ASSERT_FALSE(world.body(0).asleep) << "step " << step;
    }
}

} // namespace
} // namespace rubble
