// tests/gpu/tunnelling_device_test.cpp: fast crates against a thin static box wall on the
// device's SAT + PGS path stop in front of it, as on the CPU (tests/physics/tunnelling_test.cpp).
#include <algorithm>

#include "gpu_fixture.h"

namespace rubble {
namespace {

class DeviceTunnelling : public test::GpuTest {};

// 50 crates of 0.2 m fired at 200 m/s (3.3 m a step at 60 Hz), tumbling, at a static box wall
// 5 cm thick; the device's SAT path widens every pair's margin by how much it can close.
TEST_F(DeviceTunnelling, CratesAt200MetresASecondStopAtAThinBoxWall) {
    World w = deviceWorld(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "collision": {"method": "sat"}},
      "shapes": {"wall": {"type": "box", "half_extents": [0.025, 3, 3]},
                 "crate": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}},
      "bodies": [{"name": "wall", "shape": "wall", "static": true, "position": [0, 2, 0]}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [1, 5, 10],
                      "origin": [-2.5, 0.5, -2.25], "spacing": [1, 0.5, 0.5],
                      "rotation_jitter": 3.14, "seed": 3, "name_prefix": "c",
                      "linear_velocity": [200, 0, 0], "angular_velocity": [3, 7, -5]}]})");
    ASSERT_EQ(w.bodyCount(), 51u);
    float farthest = -1e9f;
    for (int i = 0; i < 60; ++i) {
        ASSERT_TRUE(w.step().ok()) << "step " << i;
        for (std::uint32_t b = 1; b < w.bodyCount(); ++b)
            farthest = std::max(farthest, w.body(b).position.x);
    }
    // The wall's near face is at x = -0.025: every crate's centre stays in front of it.
    EXPECT_LT(farthest, -0.025f) << "a crate went into or through the wall";
    // They did reach it: the front row starts 2.5 m away and arrives within a step.
    EXPECT_GT(farthest, -0.2f);
}

} // namespace
} // namespace rubble
