// tests/gpu/energy_watch_test.cpp: the blow-up watch of a device world on the device's sum of
// the bodies' energy (host/world/blowup_check.cpp, kernels/integrate.cl sumBodyEnergy): a steady
// step reads no bodies back, a blow-up still stops the run naming the body, and bodies read
// every few steps are those of a run that reads them every step.
#include <string>
#include <vector>

#include "gpu_fixture.h"
#include "support/physics_cases.h"

namespace rubble {
namespace {

class EnergyWatch : public test::GpuTest {
  protected:
    // A world of `json` on the device with SAT and PGS, colored by the device's plan (what a GPU
    // runs) or by the host's default plan, sleeping or kept awake.
    World satWorld(const std::string& json, bool devicePlan = true, bool sleep = true) {
        Scene scene = sceneOf(json);
        scene.simulation.backend = Backend::OpenCl;
        scene.simulation.collision.method = CollisionMethod::Sat;
        scene.simulation.solver.type = SolverType::Pgs;
        scene.simulation.sleep = sleep;
        RunOptions run;
        if (devicePlan) {
            run.pgsBlocks = 0;
            run.pgsColoring = PgsColoring::Device;
        }
        return worldOf(scene, run);
    }
    static std::uint64_t bodyReads(const World& w) { return w.deviceBodyReads(); }
};

// Sixty crates settling in a block: after the watch's first step, steps with nothing asked of
// the host read no bodies back; a query reads them once, however many follow in that step.
TEST_F(EnergyWatch, SteadyStepsReadNoBodies) {
    World w = satWorld(test::crateBlockScene(5, 3, 4));
    ASSERT_TRUE(w.step().ok());
    const std::uint64_t first = bodyReads(w);
    EXPECT_EQ(first, 1u); // the watch's reference
    for (int step = 2; step <= 60; ++step) ASSERT_TRUE(w.step().ok()) << "step " << step;
    EXPECT_EQ(bodyReads(w), first);
    const BodyState a = w.body(5);
    const BodyState b = w.body(6);
    EXPECT_EQ(bodyReads(w), first + 1);
    EXPECT_GT(a.position.y, 0.0f);
    EXPECT_GT(b.position.y, 0.0f);
    ASSERT_TRUE(w.step().ok());
    EXPECT_EQ(bodyReads(w), first + 1);
}

// The run command's blow-ups (tests/unit/run_command_test.cpp) on the device with the host's
// plan, which steps these scenes as the CPU does: the same error, the body named, in the CPU
// run's step.
TEST_F(EnergyWatch, BlowUpsStopTheRunNamingTheBody) {
    struct Case {
        const char* scene;
        const char* where;
    };
    const Case cases[] = {
        {R"({"format": "rubble-scene", "version": 1,
           "simulation": {"dt": 1, "gravity": [0, -1e6, 0]},
           "shapes": {"g": {"type": "plane", "normal": [0, 1, 0]},
                      "c": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
           "bodies": [{"name": "floor", "shape": "g", "static": true},
                      {"name": "crate", "shape": "c", "mass": 1, "position": [0, 0.5, 0]}]})",
         "body crate"},
        {R"({"format": "rubble-scene", "version": 1, "simulation": {"gravity": [0, 0, 0]},
           "shapes": {"c": {"type": "box", "half_extents": [1, 0.2, 0.5]}},
           "bodies": [{"name": "spinner", "shape": "c", "mass": 1,
                       "angular_velocity": [1e6, 3e5, 0]}]})",
         "body spinner"},
    };
    for (const Case& c : cases) {
        Scene cpuScene = sceneOf(c.scene);
        cpuScene.simulation.collision.method = CollisionMethod::Sat;
        World cpu = worldOf(cpuScene);
        World device = satWorld(c.scene, false);
        Status cpuFailed, deviceFailed;
        std::int64_t cpuStep = 0, deviceStep = 0;
        for (int step = 0; step < 20 && cpuFailed.ok(); ++step) cpuFailed = cpu.step();
        cpuStep = cpu.stepIndex();
        for (int step = 0; step < 20 && deviceFailed.ok(); ++step) deviceFailed = device.step();
        deviceStep = device.stepIndex();
        ASSERT_FALSE(cpuFailed.ok()) << c.where;
        ASSERT_FALSE(deviceFailed.ok()) << c.where;
        EXPECT_EQ(deviceFailed.error().kind, ErrorKind::Numerical)
            << deviceFailed.error().describe();
        EXPECT_EQ(deviceFailed.error().where, c.where) << deviceFailed.error().describe();
        EXPECT_EQ(deviceFailed.error().where, cpuFailed.error().where);
        EXPECT_NE(
            deviceFailed.error().message.find("the bodies' energy (kinetic and potential) grew"),
            std::string::npos)
            << deviceFailed.error().message;
        EXPECT_EQ(deviceStep, cpuStep) << c.where;
    }
}

// Positions read every fifth step (as trajectory rows are) are the bits of a run that reads
// every step, and only those steps read the bodies (kept awake: every step moves them).
TEST_F(EnergyWatch, RowsEveryFewStepsAreThoseOfARunReadingEveryStep) {
    const std::string scene = test::crateBlockScene(4, 3, 3);
    World everyStep = satWorld(scene, true, false), everyFifth = satWorld(scene, true, false);
    const std::size_t floats = 3 * everyStep.bodyCount();
    std::vector<float> a(floats), b(floats);
    ASSERT_TRUE(everyFifth.step().ok());
    ASSERT_TRUE(everyStep.step().ok());
    const std::uint64_t before = bodyReads(everyFifth);
    for (int step = 2; step <= 80; ++step) {
        ASSERT_TRUE(everyStep.step().ok());
        ASSERT_TRUE(everyFifth.step().ok());
        ASSERT_TRUE(everyStep.readPositions(0, a).ok());
        if (step % 5 != 0) continue;
        ASSERT_TRUE(everyFifth.readPositions(0, b).ok());
        for (std::size_t k = 0; k < floats; ++k)
            ASSERT_EQ(a[k], b[k]) << "step " << step << ", float " << k;
    }
    EXPECT_EQ(bodyReads(everyFifth) - before, 80u / 5);
}

} // namespace
} // namespace rubble
