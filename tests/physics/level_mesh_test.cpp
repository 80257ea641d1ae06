// tests/physics/level_mesh_test.cpp: bodies on static triangle meshes and height fields on the
// CPU pipeline, against the same bodies on a plane: resting height, sliding without bumps at
// the plane's deceleration, and a crate pile at rest on a height field.
#include <cmath>
#include <sstream>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "support/level_cases.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// One box on a floor: a plane, or the static mesh `obj` (a path) when given.
World boxOnFloor(const std::string& obj, float friction) {
    const std::string floor =
        obj.empty() ? R"({"type": "plane", "normal": [0, 1, 0], "offset": 0})"
                    : R"({"type": "mesh", "file": ")" + obj + R"("})";
    return test::worldFromText(
        R"({"format": "rubble-scene", "version": 1,
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

TEST(LevelMesh, CratePileRestsOnAHeightField) {
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
    float worst = 0.0f;
    std::string who;
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
                if (below > worst) worst = below, who = w.bodyName(b);
            }
        }
    }
    for (std::uint32_t b = 1; b < w.bodyCount(); ++b)
        EXPECT_LT(glm::length(w.body(b).position - start[b]), 0.03f)
            << w.bodyName(b) << " is still moving, m in 2 s";
    EXPECT_LT(worst, 0.01f) << who << " is that far below the surface, m";
}

} // namespace
} // namespace rubble
