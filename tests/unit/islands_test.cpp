// tests/unit/islands_test.cpp: host/dynamics/islands: islands over contacts and joints, the
// sleep timer, and waking.
#include "host/dynamics/islands.h"

#include <gtest/gtest.h>

#include "host/core/math.h"
#include "host/dynamics/joints.h"

namespace rubble {
namespace {

// Bodies 0..n-2 dynamic 1 kg, body n-1 static; all at rest unless told.
struct Sleepers {
    std::vector<shared::BodyMass> masses;
    std::vector<shared::BodyVelocity> velocities;
    std::vector<shared::BodyMomentum> momenta;
    std::vector<Manifold> manifolds;
    std::vector<JointDesc> joints;
    std::vector<float> radii;
    SleepState state;

    explicit Sleepers(std::uint32_t n) {
        shared::BodyMass dynamic{};
        dynamic.mass = dynamic.inverseMass = 1.0f;
        masses.assign(n, dynamic);
        masses[n - 1] = shared::BodyMass{};
        masses[n - 1].flags = RUBBLE_BODY_STATIC;
        velocities.assign(n, shared::BodyVelocity{});
        momenta.assign(n, shared::BodyMomentum{});
        radii.assign(n, 0.5f);
    }
    void touch(std::uint32_t a, std::uint32_t b) {
        Manifold m;
        m.a = a;
        m.b = b;
        m.count = 1;
        manifolds.push_back(m);
    }
    void move(std::uint32_t i, glm::vec3 v) {
        velocities[i].linear = toFloat4(v);
        momenta[i].linear = toFloat4(v);
    }
    SleepReport step(int n = 1) {
        SleepReport r;
        for (int i = 0; i < n; ++i)
            r = updateSleep(manifolds, joined(), radii, masses, velocities, momenta, 0.1f, state);
        return r;
    }
    // Stage wake with the velocities as the approach, over the joints' pairs.
    std::uint32_t wake() {
        return wakeIslands(manifolds, joined(), radii, masses, velocities, state);
    }
    // The joints' body pairs as the world keeps them.
    std::vector<BodyPair> joined() const { return joinedPairs(joints); }
    bool asleep(std::uint32_t i) const { return (masses[i].flags & RUBBLE_BODY_ASLEEP) != 0; }
};

TEST(Islands, StillBodiesSleepAfterTheTimeToSleep) {
    Sleepers s(3);
    s.touch(0, 2);
    s.step(4); // 0.4 s
    EXPECT_FALSE(s.asleep(0));
    const SleepReport r = s.step(1);
    EXPECT_TRUE(s.asleep(0));
    EXPECT_TRUE(s.asleep(1));
    EXPECT_FALSE(s.asleep(2)) << "static bodies are not part of islands";
    EXPECT_EQ(r.asleepBodies, 2u);
    EXPECT_EQ(r.islands, 2u) << "the static body does not join 0 and 1";
}

TEST(Islands, OneMovingBodyKeepsItsIslandAwake) {
    Sleepers s(5);
    s.touch(0, 1);
    s.touch(1, 2);
    s.move(2, {0.2f, 0, 0});
    s.move(3, {0.01f, 0, 0}); // slow: below the threshold
    const SleepReport r = s.step(10);
    EXPECT_FALSE(s.asleep(0));
    EXPECT_FALSE(s.asleep(1));
    EXPECT_FALSE(s.asleep(2));
    EXPECT_TRUE(s.asleep(3));
    EXPECT_EQ(r.islands, 2u);
    // Asleep means still: velocity and momentum zeroed.
    EXPECT_EQ(s.velocities[3].linear.x, 0.0f);
    EXPECT_EQ(s.momenta[3].linear.x, 0.0f);
}

TEST(Islands, TurningCountsAtTheRim) {
    // 0.08 rad/s at a radius of 0.5 m moves the rim at 4 cm/s: slow; at 1 m, 8 cm/s: not.
    Sleepers s(3);
    s.velocities[0].angular = s.velocities[1].angular = shared::vec4(0, 0.08f, 0);
    s.radii[1] = 1.0f;
    s.step(10);
    EXPECT_TRUE(s.asleep(0));
    EXPECT_FALSE(s.asleep(1));
}

TEST(Islands, JointsJoinIslands) {
    Sleepers s(3);
    JointDesc j;
    j.a = 0;
    j.b = 1;
    s.joints.push_back(j);
    s.move(1, {1, 0, 0});
    s.step(10);
    EXPECT_FALSE(s.asleep(0));
}

TEST(Islands, AwakeBodyTouchingASleepingGroupWakesAllOfIt) {
    Sleepers s(5);
    s.touch(0, 1);
    s.touch(1, 2);
    s.step(6);
    ASSERT_TRUE(s.asleep(0) && s.asleep(1) && s.asleep(2) && s.asleep(3));
    // Asleep, pairs between sleeping bodies are not collided: only 3 touches 2 now.
    s.manifolds.clear();
    s.touch(2, 3);
    s.masses[3].flags &= ~RUBBLE_BODY_ASLEEP; // woken from outside
    s.move(3, {-1, 0, 0});
    const SleepReport r = s.step(1);
    EXPECT_FALSE(s.asleep(0));
    EXPECT_FALSE(s.asleep(1));
    EXPECT_FALSE(s.asleep(2));
    EXPECT_EQ(r.woken, 3u);
}

TEST(Islands, SlowBodyTouchingASleepingGroupLetsItSleepAndJoinsIt) {
    Sleepers s(4);
    s.touch(0, 1);
    s.move(2, {1, 0, 0});
    s.step(6);
    ASSERT_TRUE(s.asleep(0) && s.asleep(1));
    ASSERT_FALSE(s.asleep(2));
    // 2 has stopped against 1: slow, but not for long. 0 and 1 stay asleep.
    s.move(2, {0.01f, 0, 0});
    s.manifolds.clear();
    s.touch(1, 2);
    EXPECT_EQ(s.step(1).woken, 0u);
    EXPECT_TRUE(s.asleep(0) && s.asleep(1));
    // Half a second later all three sleep as one group, and wake as one.
    s.step(5);
    ASSERT_TRUE(s.asleep(2));
    s.manifolds.clear();
    s.masses[2].flags &= ~RUBBLE_BODY_ASLEEP;
    EXPECT_EQ(s.step(1).woken, 2u);
}

TEST(Islands, BodyWokenFromOutsideStartsItsSlowTimeAgain) {
    Sleepers s(2);
    s.step(6);
    ASSERT_TRUE(s.asleep(0));
    s.masses[0].flags &= ~RUBBLE_BODY_ASLEEP; // an API call, with no lasting push
    s.step(1);
    EXPECT_FALSE(s.asleep(0)) << "half a second again before it sleeps";
    s.step(5);
    EXPECT_TRUE(s.asleep(0));
}

// Stage wake, before the rows: the group of a sleeping body that a restless one touches wakes
// whole, before the solve; a slow one wakes nothing.
TEST(Islands, WakeBeforeTheSolveTakesTheWholeGroupTouchedByAMovingBody) {
    Sleepers s(5);
    s.touch(0, 1);
    s.touch(1, 2);
    s.step(6);
    ASSERT_TRUE(s.asleep(0) && s.asleep(1) && s.asleep(2) && s.asleep(3));
    s.manifolds.clear();
    s.touch(2, 3);
    s.masses[3].flags &= ~RUBBLE_BODY_ASLEEP;
    s.state.wasAsleep[3] = 0; // awake for long, and slow: it wakes nothing
    s.move(3, {-0.01f, 0, 0});
    EXPECT_EQ(s.wake(), 0u);
    EXPECT_TRUE(s.asleep(0) && s.asleep(1) && s.asleep(2));
    s.move(3, {-1, 0, 0}); // moving: it wakes the group of the body it touches, 0, 1 and 2
    EXPECT_EQ(s.wake(), 3u);
    EXPECT_FALSE(s.asleep(0) || s.asleep(1) || s.asleep(2));
    EXPECT_EQ(s.wake(), 0u) << "nothing left asleep to wake";
}

TEST(Islands, WakeBeforeTheSolveTakesTheGroupOfABodyWokenFromOutside) {
    Sleepers s(4);
    s.touch(0, 1);
    s.touch(1, 2);
    JointDesc j;
    j.a = 2;
    j.b = 0;
    s.joints.push_back(j);
    s.step(6);
    ASSERT_TRUE(s.asleep(0) && s.asleep(1) && s.asleep(2));
    s.manifolds.clear();
    s.masses[2].flags &= ~RUBBLE_BODY_ASLEEP; // an explosion, or the API
    EXPECT_EQ(s.wake(), 2u);
    EXPECT_FALSE(s.asleep(0) || s.asleep(1));
    // updateSleep sees them all as woken from outside: half a second again before they sleep.
    s.step(1);
    EXPECT_FALSE(s.asleep(0) || s.asleep(1) || s.asleep(2));
}

} // namespace
} // namespace rubble
