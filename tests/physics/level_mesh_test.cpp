// tests/physics/level_mesh_test.cpp: bodies on static triangle meshes and height fields on the
// CPU pipeline, against the same bodies on a plane: resting height, sliding without bumps at
// the plane's deceleration, and a crate pile at rest on a height field; the same with contact
// recycling.
#include <cmath>
#include <sstream>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "support/level_cases.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// One box on a floor: a plane, or the static mesh `obj` (a path) when given; with contact
// recycling when asked.
World boxOnFloor(const std::string& obj, float friction, bool recycle = false) {
    const std::string floor =
        obj.empty() ? R"({"type": "plane", "normal": [0, 1, 0], "offset": 0})"
                    : R"({"type": "mesh", "file": ")" + obj + R"("})";
    return test::worldFromText(
        R"({"format": "rubble-scene", "version": 1,
            "simulation": {"collision": {"recycle_contacts": )" +
        std::string(recycle ? "true" : "false") + R"(}},
            "materials": {"default": {"friction": )" + std::to_string(friction) + R"(}},
            "shapes": {"floor": )" + floor + R"(,
                       "crate": {"type": "box", "half_extents": [0.5, 0.25, 0.4]}},
            "bodies": [{"name": "floor", "shape": "floor", "static": true},
                       {"name": "crate", "shape": "crate", "mass": 2,
                        "position": [0.13, 0.3, 0.07]}]})");
}

std::string meshFile(int n, float cell) {
    const std::string dir = test::tempDir("level_mesh");
    const std::string path = dir + "/floor.obj";
    test::writeText(path, test::flatGridObj(n, cell));
    return path;
}

TEST(LevelMesh, BoxRestsAtThePlanesHeight) {
    World plane = boxOnFloor("", 0.5f);
    World mesh = boxOnFloor(meshFile(20, 0.5f), 0.5f);
    ASSERT_TRUE(test::stepWorld(plane, 240));
    ASSERT_TRUE(test::stepWorld(mesh, 240));
    const std::uint32_t crate = *plane.findBody("crate");
    EXPECT_NEAR(mesh.body(crate).position.y, plane.body(crate).position.y, 2e-4f);
    EXPECT_NEAR(mesh.body(crate).position.y, 0.25f, 0.01f);
    EXPECT_LT(glm::length(mesh.body(crate).linearVelocity), 1e-3f);
    // Level: no tilt.
    EXPECT_GT((mesh.body(crate).orientation * glm::vec3(0, 1, 0)).y, 0.99999f);
}

TEST(LevelMesh, BoxSlidesOverManyTrianglesAsOnAPlane) {
    // 100 x 100 quads of 0.5 m; the box crosses about 20 of them along x and as many diagonals.
    World plane = boxOnFloor("", 0.3f);
    World mesh = boxOnFloor(meshFile(100, 0.5f), 0.3f);
    const std::uint32_t crate = *plane.findBody("crate");
    test::expectSlidesAsOnAPlane(plane, mesh, crate);
    EXPECT_LT(glm::length(mesh.body(crate).angularVelocity), 1e-2f);
}

TEST(LevelMesh, BoxRestsAtTheSameHeightRecyclingContacts) {
    // With its manifolds recycled (in 4 steps of 5 once it lands, until it sleeps after about
    // half a second), the box rests where it rests without (within 1 mm), level and still.
    const std::string floor = meshFile(20, 0.5f);
    World fresh = boxOnFloor(floor, 0.5f);
    World recycled = boxOnFloor(floor, 0.5f, true);
    const std::uint32_t crate = *fresh.findBody("crate");
    for (int step = 0; step < 240; ++step) {
        ASSERT_TRUE(test::stepWorld(fresh, 1));
        ASSERT_TRUE(test::stepWorld(recycled, 1));
        ASSERT_NEAR(recycled.body(crate).position.y, fresh.body(crate).position.y, 1e-3f)
            << "step " << step;
    }
    EXPECT_NEAR(recycled.body(crate).position.y, 0.25f, 0.01f);
    EXPECT_LT(glm::length(recycled.body(crate).linearVelocity), 1e-3f);
    EXPECT_GT((recycled.body(crate).orientation * glm::vec3(0, 1, 0)).y, 0.99999f);
}

TEST(LevelMesh, BoxSlidesOverManyTrianglesRecyclingContacts) {
    // At 5 m/s the box moves past the recycling limit every step: fresh manifolds, no bumps,
    // the plane's deceleration (both floors recycling).
    World plane = boxOnFloor("", 0.3f, true);
    World mesh = boxOnFloor(meshFile(100, 0.5f), 0.3f, true);
    const std::uint32_t crate = *plane.findBody("crate");
    test::expectSlidesAsOnAPlane(plane, mesh, crate);
    EXPECT_LT(glm::length(mesh.body(crate).angularVelocity), 1e-2f);
}

// The heights of the pile's field: two bumps and a dip, m.
float fieldHeight(int i, int j) {
    const float x = float(i) * 0.5f - 5.0f, z = float(j) * 0.5f - 5.0f;
    return 0.6f * std::exp(-0.2f * ((x - 2) * (x - 2) + z * z)) +
           0.4f * std::exp(-0.3f * ((x + 2) * (x + 2) + (z - 1) * (z - 1))) -
           0.3f * std::exp(-0.5f * (x * x + (z + 2) * (z + 2)));
}

// The surface's height at (x, z), over the triangles the field is made of.
float surfaceAt(float x, float z) {
    const float u = (x + 5.0f) / 0.5f, v = (z + 5.0f) / 0.5f;
    const int i = std::clamp(int(std::floor(u)), 0, 19), j = std::clamp(int(std::floor(v)), 0, 19);
    const float fx = u - float(i), fz = v - float(j);
    const float a = fieldHeight(i, j), b = fieldHeight(i + 1, j), c = fieldHeight(i, j + 1),
                d = fieldHeight(i + 1, j + 1);
    if (fx + fz <= 1.0f) return a + fx * (b - a) + fz * (c - a);
    return d + (1.0f - fx) * (c - d) + (1.0f - fz) * (b - d);
}

// How a pile ends on the height field: over its last 2 s, the deepest crate corner below the
// surface and the largest distance a crate moved, m, and the crates that did.
struct PileEnd {
    float deepest = 0.0f, moved = 0.0f;
    std::string deepestCrate, movedCrate;
};

// 50 crates dropped on a 10 x 10 m height field, 13 s to come down and 2 s watched, recycling
// contacts or not.
void pileOnAHeightField(bool recycle, PileEnd& end) {
    std::ostringstream heights;
    heights << "[";
    for (int j = 0; j <= 20; ++j) {
        heights << (j ? ", [" : "[");
        for (int i = 0; i <= 20; ++i) heights << (i ? ", " : "") << fieldHeight(i, j);
        heights << "]";
    }
    heights << "]";
    World w = test::worldFromText(
        R"({"format": "rubble-scene", "version": 1,
            "simulation": {"collision": {"recycle_contacts": )" +
        std::string(recycle ? "true" : "false") + R"(}},
            "materials": {"default": {"friction": 0.8}},
            "shapes": {"hill": {"type": "heightfield", "spacing": [0.5, 0.5], "heights": )" +
        heights.str() + R"(},
                       "crate": {"type": "box", "half_extents": [0.25, 0.25, 0.25]}},
            "bodies": [{"name": "hill", "shape": "hill", "static": true}],
            "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [5, 2, 5],
                            "origin": [-2.0, 1.5, -2.0], "spacing": [1.0, 0.8, 1.0],
                            "rotation_jitter": 0.3, "seed": 3, "name_prefix": "crate"}]})");
    ASSERT_TRUE(test::stepWorld(w, 780)); // 13 s to come down
    // Over the last 2 s: how deep any corner goes below the surface, and how far each crate
    // moves (the pile has come to rest; a crate leaning on another on a bump may still jitter
    // in place instead of sleeping, so rest is a bound on the motion).
    const std::vector<glm::vec3> start = test::positionsOf(w);
    for (int step = 0; step < 120; ++step) {
        ASSERT_TRUE(test::stepWorld(w, 1));
        for (std::uint32_t b = 1; b < w.bodyCount(); ++b) {
            const BodyState s = w.body(b);
            for (int k = 0; k < 8; ++k) {
                const glm::vec3 corner =
                    s.position + s.orientation * (0.25f * glm::vec3(k & 1 ? 1 : -1,
                                                                     k & 2 ? 1 : -1,
                                                                     k & 4 ? 1 : -1));
                ASSERT_LT(std::abs(corner.x), 5.0f) << w.bodyName(b) << " left the field";
                ASSERT_LT(std::abs(corner.z), 5.0f) << w.bodyName(b) << " left the field";
                const float below = surfaceAt(corner.x, corner.z) - corner.y;
                if (below > end.deepest) end.deepest = below, end.deepestCrate = w.bodyName(b);
            }
        }
    }
    for (std::uint32_t b = 1; b < w.bodyCount(); ++b) {
        const float moved = glm::length(w.body(b).position - start[b]);
        if (moved > end.moved) end.moved = moved, end.movedCrate = w.bodyName(b);
    }
}

TEST(LevelMesh, CratePileRestsOnAHeightField) {
    PileEnd end;
    pileOnAHeightField(false, end);
    EXPECT_LT(end.moved, 0.03f) << end.movedCrate << " is still moving, m in 2 s";
    EXPECT_LT(end.deepest, 0.01f) << end.deepestCrate << " is that far below the surface, m";
}

TEST(LevelMesh, CratePileRestsOnAHeightFieldRecyclingContacts) {
    // Recycled manifolds leave the pile where fresh ones do: no corner more than 1 cm below the
    // surface nor 1 mm deeper than without recycling, and the crates as still (the one leaning
    // on another on a bump jitters by about 3 cm in 2 s either way).
    PileEnd fresh, recycled;
    pileOnAHeightField(false, fresh);
    pileOnAHeightField(true, recycled);
    EXPECT_LT(recycled.deepest, 0.01f) << recycled.deepestCrate << " is that far below, m";
    EXPECT_LT(recycled.deepest, fresh.deepest + 0.001f) << recycled.deepestCrate;
    EXPECT_LT(recycled.moved, fresh.moved + 0.005f) << recycled.movedCrate << " moves, m in 2 s";
}

} // namespace
} // namespace rubble
