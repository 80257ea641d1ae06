// tests/physics/tunnelling_test.cpp: fast bodies against thin walls, boxes and triangle meshes,
// do not pass through them (speculative contacts: host/collision/sat_collision.cpp grows each
// pair's margin by how much closer the bodies can come in a step).
#include <algorithm>
#include <cmath>
#include <sstream>

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

// An OBJ of the box [-h, h] (each axis) with every face cut into a grid of quads of side at most
// `cell`, wound counter-clockwise seen from outside: a closed triangle mesh with many seams.
std::string boxObj(const float h[3], float cell) {
    std::ostringstream obj;
    int vertices = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = -1; side <= 1; side += 2) {
            // (u, v, axis) is right-handed, so u x v = +axis; the -axis face swaps u and v.
            int u = (axis + 1) % 3, v = (axis + 2) % 3;
            if (side < 0) std::swap(u, v);
            const int nu = std::max(1, int(std::ceil(2.0f * h[u] / cell)));
            const int nv = std::max(1, int(std::ceil(2.0f * h[v] / cell)));
            const int first = vertices + 1;
            for (int j = 0; j <= nv; ++j)
                for (int i = 0; i <= nu; ++i) {
                    float p[3];
                    p[axis] = float(side) * h[axis];
                    p[u] = -h[u] + 2.0f * h[u] * float(i) / float(nu);
                    p[v] = -h[v] + 2.0f * h[v] * float(j) / float(nv);
                    obj << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
                    ++vertices;
                }
            for (int j = 0; j < nv; ++j)
                for (int i = 0; i < nu; ++i) {
                    const int a = first + j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
                    obj << "f " << a << " " << b << " " << d << "\nf " << a << " " << d << " " << c
                        << "\n";
                }
        }
    return obj.str();
}

// Crates fired at 200 m/s (3.3 m a step at 60 Hz) at a static wall 5 cm thick, tumbling. The
// wall is a box, or (meshFile given) the same box as a static triangle mesh.
std::string crateVolleyScene(bool continuous, const std::string& meshFile = "") {
    const std::string wall = meshFile.empty()
                                 ? R"({"type": "box", "half_extents": [0.025, 3, 3]})"
                                 : R"({"type": "mesh", "file": ")" + meshFile + R"("})";
    return std::string(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "continuous": )") +
           (continuous ? "true" : "false") + R"(},
      "shapes": {"wall": )" + wall + R"(,
                 "crate": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}},
      "bodies": [{"name": "wall", "shape": "wall", "static": true, "position": [0, 2, 0]}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [1, 5, 10],
                      "origin": [-2.5, 0.5, -2.25], "spacing": [1, 0.5, 0.5],
                      "rotation_jitter": 3.14, "seed": 3, "name_prefix": "c",
                      "linear_velocity": [200, 0, 0], "angular_velocity": [3, 7, -5]}]})";
}

// The farthest any crate's centre gets along x over a second.
float farthestCrate(World& w) {
    float farthest = -1e9f;
    for (int i = 0; i < 60; ++i) {
        EXPECT_TRUE(w.step().ok());
        for (std::uint32_t b = 1; b < w.bodyCount(); ++b)
            farthest = std::max(farthest, w.body(b).position.x);
    }
    return farthest;
}

TEST(Tunnelling, CratesAt200MetresASecondStopAtAThinWall) {
    World w = test::worldFromText(crateVolleyScene(true));
    ASSERT_EQ(w.bodyCount(), 51u);
    // The wall's near face is at x = -0.025: every crate's centre stays in front of it.
    EXPECT_LT(farthestCrate(w), -0.025f) << "a crate went into or through the wall";
}

// The volley's wall as a closed triangle mesh, its faces cut into 0.25 m quads (2,016
// triangles), so that crates also hit it on the seams between triangles.
std::string meshWallFile() {
    const float half[3] = {0.025f, 3.0f, 3.0f};
    const std::string path = test::tempDir("tunnelling") + "/wall.obj";
    test::writeText(path, boxObj(half, 0.25f));
    return path;
}

TEST(Tunnelling, CratesAt200MetresASecondStopAtAThinMeshWall) {
    World w = test::worldFromText(crateVolleyScene(true, meshWallFile()));
    ASSERT_EQ(w.bodyCount(), 51u);
    ASSERT_NEAR(w.body(0).position.x, 0.0f, 1e-5f)
        << "a closed mesh is placed by its centre of mass";
    EXPECT_LT(farthestCrate(w), -0.025f) << "a crate went into or through the mesh wall";
}

TEST(Tunnelling, WithoutContinuousCollisionTheCratesPassThrough) {
    // The same volleys with the margins not widened: what continuous collision stops.
    for (const std::string& mesh : {std::string(), meshWallFile()}) {
        SCOPED_TRACE(mesh.empty() ? "box wall" : "mesh wall");
        World w = test::worldFromText(crateVolleyScene(false, mesh));
        ASSERT_TRUE(test::stepWorld(w, 3));
        std::uint32_t through = 0;
        for (std::uint32_t b = 1; b < w.bodyCount(); ++b) through += w.body(b).position.x > 0.0f;
        EXPECT_GT(through, 40u);
    }
}

} // namespace
} // namespace rubble
