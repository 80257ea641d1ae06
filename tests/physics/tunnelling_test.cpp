// tests/physics/tunnelling_test.cpp: fast bodies against thin walls do not pass through them
// (speculative contacts: host/collision/sat_collision.cpp grows each pair's margin by how much
// closer the bodies can come in a step).
#include <gtest/gtest.h>

#include "support/test_util.h"

namespace rubble {
namespace {

std::string thinSlabScene(const std::string& mover, const std::string& moverShape) {
    return R"({"format": "rubble-scene", "version": 1, "simulation": {"dt": 0.016666667},
      "shapes": {"slab": {"type": "box", "half_extents": [2, 0.025, 2]},
                 "wall": {"type": "box", "half_extents": [0.025, 2, 2]},
                 "mover": )" + moverShape + R"(},
      "bodies": [{"name": "slab", "shape": "slab", "static": true},
                 {"name": "wall", "shape": "wall", "static": true, "position": [3, 2.1, 0]},
                 )" + mover + "]}";
}

TEST(Tunnelling, SmallBoxFallingFastLandsOnAThinSlab) {
    // From 30 m it hits at 24 m/s: 0.4 m a step, four times its size, eight times the slab.
    World w = test::worldFromText(thinSlabScene(
        R"({"name": "pebble", "shape": "mover", "mass": 0.2, "position": [0.3, 30, 0.2],
            "orientation": [0.96, 0.2, 0.1, 0.17]})",
        R"({"type": "box", "half_extents": [0.05, 0.05, 0.05]})"));
    const std::uint32_t pebble = *w.findBody("pebble");
    float lowest = 1e9f;
    for (int i = 0; i < 240; ++i) {
        ASSERT_TRUE(w.step().ok());
        lowest = std::min(lowest, w.body(pebble).position.y);
    }
    // On top of the slab (top face at y = 0.025), never below it.
    EXPECT_GT(lowest, 0.025f) << "the pebble went into or through the slab";
    EXPECT_NEAR(w.body(pebble).position.y, 0.075f, 0.02f);
    EXPECT_LT(glm::length(w.body(pebble).linearVelocity), 0.05f);
}

TEST(Tunnelling, FastSphereStopsAtAThinWall) {
    // 40 m/s horizontally: 0.67 m a step against a 5 cm wall.
    World w = test::worldFromText(thinSlabScene(
        R"({"name": "shot", "shape": "mover", "mass": 0.05, "position": [-1, 2, 0],
            "linear_velocity": [40, 0, 0]})",
        R"({"type": "sphere", "radius": 0.04})"));
    const std::uint32_t shot = *w.findBody("shot");
    float farthest = -1e9f;
    for (int i = 0; i < 120; ++i) {
        ASSERT_TRUE(w.step().ok());
        farthest = std::max(farthest, w.body(shot).position.x);
    }
    // The wall's near face is at x = 2.975; the sphere's centre stays a radius short of it.
    EXPECT_LT(farthest, 2.975f - 0.04f + 0.01f) << "the sphere went into or through the wall";
    EXPECT_GT(farthest, 2.8f);
}

// Crates fired at 200 m/s (3.3 m a step at 60 Hz) at a static wall 5 cm thick, tumbling.
std::string crateVolleyScene(bool continuous) {
    return std::string(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "continuous": )") +
           (continuous ? "true" : "false") + R"(},
      "shapes": {"wall": {"type": "box", "half_extents": [0.025, 3, 3]},
                 "crate": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}},
      "bodies": [{"name": "wall", "shape": "wall", "static": true, "position": [0, 2, 0]}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [1, 5, 10],
                      "origin": [-2.5, 0.5, -2.25], "spacing": [1, 0.5, 0.5],
                      "rotation_jitter": 3.14, "seed": 3, "name_prefix": "c",
                      "linear_velocity": [200, 0, 0], "angular_velocity": [3, 7, -5]}]})";
}

TEST(Tunnelling, CratesAt200MetresASecondStopAtAThinWall) {
    World w = test::worldFromText(crateVolleyScene(true));
    ASSERT_EQ(w.bodyCount(), 51u);
    float farthest = -1e9f;
    for (int i = 0; i < 60; ++i) {
        ASSERT_TRUE(w.step().ok());
        for (std::uint32_t b = 1; b < w.bodyCount(); ++b)
            farthest = std::max(farthest, w.body(b).position.x);
    }
    // The wall's near face is at x = -0.025: every crate's centre stays in front of it.
    EXPECT_LT(farthest, -0.025f) << "a crate went into or through the wall";
}

TEST(Tunnelling, WithoutContinuousCollisionTheCratesPassThrough) {
    // The same volley with the margins not widened: what continuous collision stops.
    World w = test::worldFromText(crateVolleyScene(false));
    ASSERT_TRUE(test::stepWorld(w, 3));
    std::uint32_t through = 0;
    for (std::uint32_t b = 1; b < w.bodyCount(); ++b) through += w.body(b).position.x > 0.0f;
    EXPECT_GT(through, 40u);
}

} // namespace
} // namespace rubble
