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

} // namespace
} // namespace rubble
