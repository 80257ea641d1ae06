// tests/unit/collision_world_test.cpp: host/collision/collision_world: the broad and narrow phase
// stages on whole worlds built from scene text.
#include "host/collision/collision_world.h"

#include <algorithm>
#include <cstring>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "host/core/math.h"
#include "host/world/world_state.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// A scene with a floor plane and the given bodies (JSON array items).
std::string scene(const std::string& shapes, const std::string& bodies) {
    return R"({"format": "rubble-scene", "version": 1, "name": "t",
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0}, )" +
           shapes + R"(},
      "bodies": [{"name": "floor", "shape": "floor", "static": true}, )" +
           bodies + "]}";
}

TEST(CollisionWorld, BoxOnFloorGivesFourPointsPointingUp) {
    World w = test::worldFromText(
        scene(R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]})",
              R"({"name": "c", "shape": "crate", "mass": 1, "position": [0, 0.49, 0]})"));
    WorldState& s = w.state();
    runBroadPhase(s);
    ASSERT_EQ(s.pairs.size(), 1u);
    EXPECT_EQ(s.pairs[0], (BodyPair{0, 1}));
    runNarrowPhase(s);
    ASSERT_EQ(s.manifolds.size(), 1u);
    const Manifold& m = s.manifolds[0];
    EXPECT_EQ(m.a, 0u);
    EXPECT_EQ(m.b, 1u);
    EXPECT_NEAR(m.normal.y, 1.0f, 1e-6f);
    ASSERT_EQ(m.count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(m.points[i].depth, 0.01f, 1e-5f);
        EXPECT_NEAR(m.points[i].position.y, -0.005f, 1e-5f);
        EXPECT_EQ(m.points[i].normal, m.normal);
    }
    EXPECT_EQ(s.stats.contactCount, 4u);
    EXPECT_NEAR(s.stats.largestPenetration, 0.01f, 1e-5f);
}

// Joined bodies do not collide: two overlapping boxes joined by a hinge give no pair, so no
// contact is computed, counted or drawn; the floor and the free box still meet both.
TEST(CollisionWorld, JoinedBodiesGiveNoPair) {
    const std::string text = R"({"format": "rubble-scene", "version": 1, "name": "t",
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true},
                 {"name": "a", "shape": "crate", "mass": 1, "position": [0, 0.49, 0]},
                 {"name": "b", "shape": "crate", "mass": 1, "position": [0.8, 0.49, 0]},
                 {"name": "c", "shape": "crate", "mass": 1, "position": [0.8, 1.48, 0]}],
      "joints": [{"type": "hinge", "a": "a", "b": "b", "anchor": [0.4, 0.49, 0],
                  "axis": [0, 0, 1]}]})";
    World w = test::worldFromText(text);
    WorldState& s = w.state();
    runBroadPhase(s);
    const auto has = [&](std::uint32_t a, std::uint32_t b) {
        return std::find(s.pairs.begin(), s.pairs.end(), BodyPair{a, b}) != s.pairs.end() ||
               std::find(s.pairs.begin(), s.pairs.end(), BodyPair{b, a}) != s.pairs.end();
    };
    EXPECT_FALSE(has(1, 2)); // joined, 0.2 m into each other
    EXPECT_TRUE(has(0, 1));
    EXPECT_TRUE(has(0, 2));
    EXPECT_TRUE(has(2, 3)); // c rests on b, not joined
    EXPECT_TRUE(has(1, 3)); // c overlaps a's corner region too
    runNarrowPhase(s);
    for (const Manifold& m : s.manifolds)
        EXPECT_FALSE((m.a == 1 && m.b == 2) || (m.a == 2 && m.b == 1));
    EXPECT_LT(s.stats.largestPenetration, 0.05f);
}

TEST(CollisionWorld, StackOfBoxesAndSpheres) {
    World w = test::worldFromText(scene(
        R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
           "ball": {"type": "sphere", "radius": 0.25})",
        R"({"name": "c0", "shape": "crate", "mass": 1, "position": [0, 0.499, 0]},
           {"name": "c1", "shape": "crate", "mass": 1, "position": [0, 1.497, 0]},
           {"name": "b", "shape": "ball", "mass": 1, "position": [0, 2.24, 0]},
           {"name": "far", "shape": "ball", "mass": 1, "position": [5, 3, 0]})"));
    WorldState& s = w.state();
    runBroadPhase(s);
    // floor-c0, c0-c1, c1-b; the far ball touches nothing.
    ASSERT_EQ(s.pairs.size(), 3u);
    EXPECT_EQ(s.pairs[0], (BodyPair{0, 1}));
    EXPECT_EQ(s.pairs[1], (BodyPair{1, 2}));
    EXPECT_EQ(s.pairs[2], (BodyPair{2, 3}));
    runNarrowPhase(s);
    ASSERT_EQ(s.manifolds.size(), 3u);
    EXPECT_EQ(s.manifolds[0].count, 4u);
    EXPECT_EQ(s.manifolds[1].count, 4u);
    EXPECT_EQ(s.manifolds[2].count, 1u);
    for (const Manifold& m : s.manifolds) EXPECT_GT(m.normal.y, 0.999f); // a below b
    EXPECT_NEAR(s.manifolds[1].points[0].depth, 0.002f, 1e-5f);
    EXPECT_NEAR(s.manifolds[2].points[0].depth, 0.007f, 1e-5f);
}

TEST(CollisionWorld, SphereBeforeHullAndPlaneAfterBody) {
    // The ball has the lower index than the crate on it, and the floor the higher index than
    // the ball: normals must still point from a to b.
    const std::string text = R"({"format": "rubble-scene", "version": 1, "name": "t",
      "shapes": {"ball": {"type": "sphere", "radius": 0.25},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0}},
      "bodies": [{"name": "b", "shape": "ball", "mass": 1, "position": [0, 0.248, 0]},
                 {"name": "c", "shape": "crate", "mass": 1, "position": [0, 0.997, 0]},
                 {"name": "floor", "shape": "floor", "static": true}]})";
    World w = test::worldFromText(text);
    WorldState& s = w.state();
    runBroadPhase(s);
    runNarrowPhase(s);
    ASSERT_EQ(s.manifolds.size(), 2u);
    const Manifold& ballCrate = s.manifolds[0];
    const Manifold& ballFloor = s.manifolds[1];
    EXPECT_EQ(ballCrate.a, 0u);
    EXPECT_EQ(ballCrate.b, 1u);
    EXPECT_NEAR(ballCrate.normal.y, 1.0f, 1e-6f);          // ball (a) to crate (b): up
    EXPECT_NEAR(ballCrate.points[0].depth, 0.001f, 1e-5f); // ball top 0.498, crate bottom 0.497
    EXPECT_EQ(ballFloor.a, 0u);
    EXPECT_EQ(ballFloor.b, 2u);
    EXPECT_NEAR(ballFloor.normal.y, -1.0f, 1e-6f); // ball (a) to floor (b): down
    EXPECT_NEAR(ballFloor.points[0].depth, 0.002f, 1e-5f);
}

TEST(CollisionWorld, StaticAndSleepingPairsAreSkipped) {
    World w = test::worldFromText(
        scene(R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]})",
              R"({"name": "s0", "shape": "crate", "static": true, "position": [0, 0.5, 0]},
           {"name": "s1", "shape": "crate", "static": true, "position": [0.9, 0.5, 0]},
           {"name": "d0", "shape": "crate", "mass": 1, "position": [0, 1.49, 0]},
           {"name": "d1", "shape": "crate", "mass": 1, "position": [0.9, 1.49, 0]})"));
    WorldState& s = w.state();
    runBroadPhase(s);
    // Statics with the floor and each other never; d0-d1 overlap; each d sits on both statics.
    const std::vector<BodyPair> expected{{1, 3}, {1, 4}, {2, 3}, {2, 4}, {3, 4}};
    EXPECT_EQ(s.pairs, expected);
    s.masses[3].flags |= RUBBLE_BODY_ASLEEP;
    s.masses[4].flags |= RUBBLE_BODY_ASLEEP;
    runBroadPhase(s);
    EXPECT_TRUE(s.pairs.empty());
}

// The sorted feature ids of a manifold.
std::vector<std::uint32_t> featureIds(const Manifold& m) {
    std::vector<std::uint32_t> ids;
    for (std::uint32_t i = 0; i < m.count; ++i) ids.push_back(m.points[i].feature);
    std::sort(ids.begin(), ids.end());
    return ids;
}

TEST(CollisionWorld, FeatureIdsSurviveSmallMotionAcrossSteps) {
    World w = test::worldFromText(
        scene(R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]})",
              R"({"name": "c0", "shape": "crate", "mass": 1, "position": [0, 0.498, 0]},
                 {"name": "c1", "shape": "crate", "mass": 1, "position": [0.1, 1.495, 0.05]})"));
    WorldState& s = w.state();
    runBroadPhase(s);
    runNarrowPhase(s);
    ASSERT_EQ(s.manifolds.size(), 2u);
    const std::vector<std::uint32_t> floorIds = featureIds(s.manifolds[0]);
    const std::vector<std::uint32_t> stackIds = featureIds(s.manifolds[1]);
    // Drift and turn a little for 20 steps, past the cache's reuse distance.
    for (int step = 1; step <= 20; ++step) {
        s.poses[2].position.x += 0.0003f;
        s.poses[2].position.y -= 0.0001f;
        s.poses[2].orientation = toFloat4(glm::angleAxis(0.001f * float(step), glm::vec3(0, 1, 0)));
        runBroadPhase(s);
        runNarrowPhase(s);
        ASSERT_EQ(s.manifolds.size(), 2u) << "step " << step;
        EXPECT_EQ(featureIds(s.manifolds[0]), floorIds) << "step " << step;
        EXPECT_EQ(featureIds(s.manifolds[1]), stackIds) << "step " << step;
        EXPECT_EQ(s.manifolds[1].count, 4u);
    }
}

TEST(CollisionWorld, NarrowPhaseRepeatsBitForBit) {
    const std::string text = scene(
        R"("crate": {"type": "box", "half_extents": [0.5, 0.3, 0.4]},
           "ball": {"type": "sphere", "radius": 0.3})",
        R"({"name": "c0", "shape": "crate", "mass": 1, "position": [0, 0.29, 0],
            "orientation": [0.99, 0.05, 0.1, 0.0]},
           {"name": "c1", "shape": "crate", "mass": 1, "position": [0.3, 0.85, 0.1],
            "orientation": [0.95, 0.2, 0.0, 0.1]},
           {"name": "b", "shape": "ball", "mass": 1, "position": [-0.6, 0.5, 0]})");
    World w1 = test::worldFromText(text), w2 = test::worldFromText(text);
    for (World* w : {&w1, &w2}) {
        runBroadPhase(w->state());
        runNarrowPhase(w->state());
    }
    const auto& m1 = w1.state().manifolds;
    const auto& m2 = w2.state().manifolds;
    ASSERT_EQ(m1.size(), m2.size());
    ASSERT_GE(m1.size(), 3u);
    for (std::size_t i = 0; i < m1.size(); ++i)
        EXPECT_EQ(std::memcmp(&m1[i], &m2[i], sizeof(Manifold)), 0) << "manifold " << i;
}

} // namespace
} // namespace rubble
