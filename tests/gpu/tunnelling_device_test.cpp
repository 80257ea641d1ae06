// tests/gpu/tunnelling_device_test.cpp: fast crates against a thin static wall, a box and the
// same box as triangles, on the device's SAT + PGS path stop in front of it, as on the CPU
// (tests/physics/tunnelling_test.cpp).
#include <algorithm>
#include <string>

#include "gpu_fixture.h"

namespace rubble {
namespace {

class DeviceTunnelling : public test::GpuTest {};

// The volley's scene with the wall given as the shape `wall` (JSON), its centre at (0, 4, 0).
std::string volleyAt(const std::string& wall) {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "collision": {"method": "sat"}},
      "shapes": {"floor": {"type": "plane"}, "wall": )" +
           wall + R"(,
                 "crate": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true},
                 {"name": "wall", "shape": "wall", "static": true, "position": [0, 4, 0]}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [2, 20, 25],
                      "origin": [-3, 0.5, -6], "spacing": [1, 0.3, 0.5],
                      "rotation_jitter": 3.14, "seed": 1, "name_prefix": "c",
                      "linear_velocity": [200, 0, 0], "angular_velocity": [3, 7, -5]}]})";
}

// Fires the volley for a second and checks that every crate's centre stayed in front of the
// wall's near face (x = -0.025) and that the front row did reach it (it starts 2 m away and
// arrives within a step).
void expectVolleyStops(World& w) {
    ASSERT_EQ(w.bodyCount(), 1002u);
    float farthest = -1e9f;
    for (int i = 0; i < 60; ++i) {
        const Status stepped = w.step();
        ASSERT_TRUE(stepped.ok()) << "step " << i << ": " << stepped.error().describe();
        for (std::uint32_t b = 2; b < w.bodyCount(); ++b)
            farthest = std::max(farthest, w.body(b).position.x);
    }
    EXPECT_LT(farthest, -0.025f) << "a crate went into or through the wall";
    EXPECT_GT(farthest, -0.2f);
}

// 1,000 crates of 0.2 m, 0.3 to 1 m apart, fired at 200 m/s (3.3 m a step at 60 Hz), tumbling,
// at a static box wall 5 cm thick (scenes/bench/wall_volley_1k.json): the device's SAT path
// widens every pair's margin by how much it can close, and sweeps each fast crate's box along
// its motion, so that the volley stays within the pair budget (boxes grown every way would pair
// each crate with hundreds of its neighbours and stop the run with exit 4).
TEST_F(DeviceTunnelling, CratesAt200MetresASecondStopAtAThinBoxWall) {
    World w = deviceWorld(volleyAt(R"({"type": "box", "half_extents": [0.025, 4, 8]})"));
    expectVolleyStops(w);
}

// The same volley at the same wall made of triangles (scenes/meshes/wall_5cm.obj, quads of at
// most 1 m, so that crates hit it on seams and edges; scenes/bench/wall_volley_mesh_1k.json).
TEST_F(DeviceTunnelling, CratesAt200MetresASecondStopAtAThinMeshWall) {
    World w = deviceWorld(volleyAt(R"({"type": "mesh", "file": ")" RUBBLE_SOURCE_DIR
                                   R"(/scenes/meshes/wall_5cm.obj"})"));
    expectVolleyStops(w);
}

} // namespace
} // namespace rubble
