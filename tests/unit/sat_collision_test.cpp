// tests/unit/sat_collision_test.cpp: host/collision/sat_collision: the broad and narrow phase
// stages of the SAT method on the bodies of scenes given as text.
#include "host/collision/sat_collision.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "host/core/math.h"
#include "support/stage_input.h"

namespace rubble {
namespace {

// The SAT stages on a scene's bodies, with their contacts.
struct Sat {
    explicit Sat(const std::string& text) : in(test::stageInput(text)) {}
    void broadPhase() {
        const Status st = stage.broadPhase(in.collisionScene(), in.bodies.view(), in.params(), c);
        ASSERT_TRUE(st.ok()) << st.error().describe();
    }
    void narrowPhase() {
        const Status st = stage.narrowPhase(in.collisionScene(), in.bodies.view(), in.params(), c);
        ASSERT_TRUE(st.ok()) << st.error().describe();
    }
    test::StageInput in;
    SatCollision stage{ContactForm::Manifolds};
    StepContacts c;
};

// A scene with a floor plane and the given bodies (JSON array items).
std::string scene(const std::string& shapes, const std::string& bodies) {
    return R"({"format": "rubble-scene", "version": 1, "name": "t",
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0}, )" +
           shapes + R"(},
      "bodies": [{"name": "floor", "shape": "floor", "static": true}, )" +
           bodies + "]}";
}

TEST(SatCollision, BoxOnFloorGivesFourPointsPointingUp) {
    Sat s(
        scene(R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]})",
              R"({"name": "c", "shape": "crate", "mass": 1, "position": [0, 0.49, 0]})"));
    s.broadPhase();
    ASSERT_EQ(s.c.pairs.size(), 1u);
    EXPECT_EQ(s.c.pairs[0], (BodyPair{0, 1}));
    s.narrowPhase();
    ASSERT_EQ(s.c.manifolds.size(), 1u);
    const Manifold& m = s.c.manifolds[0];
    EXPECT_EQ(m.a, 0u);
    EXPECT_EQ(m.b, 1u);
    EXPECT_NEAR(m.normal.y, 1.0f, 1e-6f);
    ASSERT_EQ(m.count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(m.points[i].depth, 0.01f, 1e-5f);
        EXPECT_NEAR(m.points[i].position.y, -0.005f, 1e-5f);
        EXPECT_EQ(m.points[i].normal, m.normal);
    }
    EXPECT_EQ(s.c.contactCount, 4u);
    EXPECT_NEAR(s.c.largestPenetration, 0.01f, 1e-5f);
}

// Joined bodies do not collide: two overlapping boxes joined by a hinge give no pair, so no
// contact is computed, counted or drawn; the floor and the free box still meet both.
TEST(SatCollision, JoinedBodiesGiveNoPair) {
    const std::string text = R"({"format": "rubble-scene", "version": 1, "name": "t",
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true},
                 {"name": "a", "shape": "crate", "mass": 1, "position": [0, 0.49, 0]},
                 {"name": "b", "shape": "crate", "mass": 1, "position": [0.8, 0.49, 0]},
                 {"name": "c", "shape": "crate", "mass": 1, "position": [0.8, 1.48, 0]}],
      "joints": [{"type": "hinge", "a": "a", "b": "b", "anchor": [0.4, 0.49, 0],
                  "axis": [0, 0, 1]}]})";
    Sat s(text);
    s.broadPhase();
    const auto has = [&](std::uint32_t a, std::uint32_t b) {
        return std::find(s.c.pairs.begin(), s.c.pairs.end(), BodyPair{a, b}) != s.c.pairs.end() ||
               std::find(s.c.pairs.begin(), s.c.pairs.end(), BodyPair{b, a}) != s.c.pairs.end();
    };
    EXPECT_FALSE(has(1, 2)); // joined, 0.2 m into each other
    EXPECT_TRUE(has(0, 1));
    EXPECT_TRUE(has(0, 2));
    EXPECT_TRUE(has(2, 3)); // c rests on b, not joined
    EXPECT_TRUE(has(1, 3)); // c overlaps a's corner region too
    s.narrowPhase();
    for (const Manifold& m : s.c.manifolds)
        EXPECT_FALSE((m.a == 1 && m.b == 2) || (m.a == 2 && m.b == 1));
    EXPECT_LT(s.c.largestPenetration, 0.05f);
}

TEST(SatCollision, StackOfBoxesAndSpheres) {
    Sat s(scene(
        R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
           "ball": {"type": "sphere", "radius": 0.25})",
        R"({"name": "c0", "shape": "crate", "mass": 1, "position": [0, 0.499, 0]},
           {"name": "c1", "shape": "crate", "mass": 1, "position": [0, 1.497, 0]},
           {"name": "b", "shape": "ball", "mass": 1, "position": [0, 2.24, 0]},
           {"name": "far", "shape": "ball", "mass": 1, "position": [5, 3, 0]})"));
    s.broadPhase();
    // floor-c0, c0-c1, c1-b; the far ball touches nothing.
    ASSERT_EQ(s.c.pairs.size(), 3u);
    EXPECT_EQ(s.c.pairs[0], (BodyPair{0, 1}));
    EXPECT_EQ(s.c.pairs[1], (BodyPair{1, 2}));
    EXPECT_EQ(s.c.pairs[2], (BodyPair{2, 3}));
    s.narrowPhase();
    ASSERT_EQ(s.c.manifolds.size(), 3u);
    EXPECT_EQ(s.c.manifolds[0].count, 4u);
    EXPECT_EQ(s.c.manifolds[1].count, 4u);
    EXPECT_EQ(s.c.manifolds[2].count, 1u);
    for (const Manifold& m : s.c.manifolds) EXPECT_GT(m.normal.y, 0.999f); // a below b
    EXPECT_NEAR(s.c.manifolds[1].points[0].depth, 0.002f, 1e-5f);
    EXPECT_NEAR(s.c.manifolds[2].points[0].depth, 0.007f, 1e-5f);
}

TEST(SatCollision, SphereBeforeHullAndPlaneAfterBody) {
    // The ball has the lower index than the crate on it, and the floor the higher index than
    // the ball: normals must still point from a to b.
    const std::string text = R"({"format": "rubble-scene", "version": 1, "name": "t",
      "shapes": {"ball": {"type": "sphere", "radius": 0.25},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0}},
      "bodies": [{"name": "b", "shape": "ball", "mass": 1, "position": [0, 0.248, 0]},
                 {"name": "c", "shape": "crate", "mass": 1, "position": [0, 0.997, 0]},
                 {"name": "floor", "shape": "floor", "static": true}]})";
    Sat s(text);
    s.broadPhase();
    s.narrowPhase();
    ASSERT_EQ(s.c.manifolds.size(), 2u);
    const Manifold& ballCrate = s.c.manifolds[0];
    const Manifold& ballFloor = s.c.manifolds[1];
    EXPECT_EQ(ballCrate.a, 0u);
    EXPECT_EQ(ballCrate.b, 1u);
    EXPECT_NEAR(ballCrate.normal.y, 1.0f, 1e-6f);          // ball (a) to crate (b): up
    EXPECT_NEAR(ballCrate.points[0].depth, 0.001f, 1e-5f); // ball top 0.498, crate bottom 0.497
    EXPECT_EQ(ballFloor.a, 0u);
    EXPECT_EQ(ballFloor.b, 2u);
    EXPECT_NEAR(ballFloor.normal.y, -1.0f, 1e-6f); // ball (a) to floor (b): down
    EXPECT_NEAR(ballFloor.points[0].depth, 0.002f, 1e-5f);
}

TEST(SatCollision, StaticAndSleepingPairsAreSkipped) {
    Sat s(
        scene(R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]})",
              R"({"name": "s0", "shape": "crate", "static": true, "position": [0, 0.5, 0]},
           {"name": "s1", "shape": "crate", "static": true, "position": [0.9, 0.5, 0]},
           {"name": "d0", "shape": "crate", "mass": 1, "position": [0, 1.49, 0]},
           {"name": "d1", "shape": "crate", "mass": 1, "position": [0.9, 1.49, 0]})"));
    s.broadPhase();
    // Statics with the floor and each other never; d0-d1 overlap; each d sits on both statics.
    const std::vector<BodyPair> expected{{1, 3}, {1, 4}, {2, 3}, {2, 4}, {3, 4}};
    EXPECT_EQ(s.c.pairs, expected);
    s.in.bodies.masses[3].flags |= RUBBLE_BODY_ASLEEP;
    s.in.bodies.masses[4].flags |= RUBBLE_BODY_ASLEEP;
    s.broadPhase();
    EXPECT_TRUE(s.c.pairs.empty());
}

// The sorted feature ids of a manifold.
std::vector<std::uint32_t> featureIds(const Manifold& m) {
    std::vector<std::uint32_t> ids;
    for (std::uint32_t i = 0; i < m.count; ++i) ids.push_back(m.points[i].feature);
    std::sort(ids.begin(), ids.end());
    return ids;
}

TEST(SatCollision, FeatureIdsSurviveSmallMotionAcrossSteps) {
    Sat s(
        scene(R"("crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]})",
              R"({"name": "c0", "shape": "crate", "mass": 1, "position": [0, 0.498, 0]},
                 {"name": "c1", "shape": "crate", "mass": 1, "position": [0.1, 1.495, 0.05]})"));
    s.broadPhase();
    s.narrowPhase();
    ASSERT_EQ(s.c.manifolds.size(), 2u);
    const std::vector<std::uint32_t> floorIds = featureIds(s.c.manifolds[0]);
    const std::vector<std::uint32_t> stackIds = featureIds(s.c.manifolds[1]);
    // Drift and turn a little for 20 steps, past the cache's reuse distance.
    for (int step = 1; step <= 20; ++step) {
        s.in.bodies.poses[2].position.x += 0.0003f;
        s.in.bodies.poses[2].position.y -= 0.0001f;
        s.in.bodies.poses[2].orientation = toFloat4(glm::angleAxis(0.001f * float(step), glm::vec3(0, 1, 0)));
        s.broadPhase();
        s.narrowPhase();
        ASSERT_EQ(s.c.manifolds.size(), 2u) << "step " << step;
        EXPECT_EQ(featureIds(s.c.manifolds[0]), floorIds) << "step " << step;
        EXPECT_EQ(featureIds(s.c.manifolds[1]), stackIds) << "step " << step;
        EXPECT_EQ(s.c.manifolds[1].count, 4u);
    }
}

TEST(SatCollision, NarrowPhaseRepeatsBitForBit) {
    const std::string text = scene(
        R"("crate": {"type": "box", "half_extents": [0.5, 0.3, 0.4]},
           "ball": {"type": "sphere", "radius": 0.3})",
        R"({"name": "c0", "shape": "crate", "mass": 1, "position": [0, 0.29, 0],
            "orientation": [0.99, 0.05, 0.1, 0.0]},
           {"name": "c1", "shape": "crate", "mass": 1, "position": [0.3, 0.85, 0.1],
            "orientation": [0.95, 0.2, 0.0, 0.1]},
           {"name": "b", "shape": "ball", "mass": 1, "position": [-0.6, 0.5, 0]})");
    Sat w1(text), w2(text);
    for (Sat* w : {&w1, &w2}) {
        w->broadPhase();
        w->narrowPhase();
    }
    const auto& m1 = w1.c.manifolds;
    const auto& m2 = w2.c.manifolds;
    ASSERT_EQ(m1.size(), m2.size());
    ASSERT_GE(m1.size(), 3u);
    for (std::size_t i = 0; i < m1.size(); ++i)
        EXPECT_EQ(std::memcmp(&m1[i], &m2[i], sizeof(Manifold)), 0) << "manifold " << i;
}

// A 100-sided disc lying on a box: faces of 100 vertices clip in the stage's buffers, which it
// sizes from the largest face (the device refuses faces of more than 16).
TEST(SatCollision, FacesOfAHundredVerticesClip) {
    std::string disc;
    for (int i = 0; i < 100; ++i) {
        const float a = 2.0f * 3.14159265f * float(i) / 100.0f;
        for (const char* y : {"-0.1", "0.1"})
            disc += (disc.empty() ? "[" : ", [") + std::to_string(0.8f * std::cos(a)) + ", " + y +
                    ", " + std::to_string(0.8f * std::sin(a)) + "]";
    }
    Sat s(scene(R"("table": {"type": "box", "half_extents": [1, 0.5, 1]},
                  "disc": {"type": "convex", "vertices": [)" +
                    disc + "]}",
                R"({"name": "table", "shape": "table", "static": true, "position": [0, 0.5, 0]},
                   {"name": "disc", "shape": "disc", "mass": 1, "position": [0, 1.095, 0]})"));
    s.broadPhase();
    s.narrowPhase();
    ASSERT_EQ(s.c.manifolds.size(), 1u);
    const Manifold& m = s.c.manifolds[0];
    EXPECT_EQ(m.a, 1u);
    EXPECT_EQ(m.b, 2u);
    EXPECT_NEAR(m.normal.y, 1.0f, 1e-6f);
    ASSERT_EQ(m.count, 4u);
    float span = 0.0f; // the largest distance between two of the points
    for (std::uint32_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(m.points[i].depth, 0.005f, 1e-5f);
        for (std::uint32_t j = 0; j < i; ++j)
            span = std::max(span, glm::length(m.points[i].position - m.points[j].position));
    }
    EXPECT_GT(span, 1.5f); // nearly a diameter (1.6 m)
}

} // namespace
} // namespace rubble
