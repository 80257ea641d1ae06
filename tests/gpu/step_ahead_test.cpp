// tests/gpu/step_ahead_test.cpp: steps run ahead of the host (host/gpu/device_step.cpp): on the
// device's plan a steady SAT step waits for nothing but its end, and a step whose round was not
// what the host assumed (here its pairs overflowed their buffers) runs again from its start and
// ends on the bits of a step that had room.
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gpu_fixture.h"
#include "support/physics_cases.h"

namespace rubble {
namespace {

class StepAhead : public test::GpuTest {
  protected:
    // A world of `json` on the device with SAT and `solver`, every element colored by the
    // device's plan (what a GPU runs), kept awake.
    World coloredWorld(const std::string& json, SolverType solver) {
        Scene scene = sceneOf(json);
        scene.simulation.backend = Backend::OpenCl;
        scene.simulation.collision.method = CollisionMethod::Sat;
        scene.simulation.solver.type = solver;
        scene.simulation.sleep = false;
        RunOptions run;
        run.pgsBlocks = 0;
        run.pgsColoring = PgsColoring::Device;
        return worldOf(scene, run);
    }
};

// Sixty crates settling in a block on a floor: once the block has settled no step waits for the
// device in its middle (no blocking read), with PGS and with the soft step.
TEST_F(StepAhead, SteadyColoredStepsWaitForNothing) {
    for (const SolverType solver : {SolverType::Pgs, SolverType::SoftStep}) {
        World w = coloredWorld(test::crateBlockScene(5, 3, 4), solver);
        const char* name = solver == SolverType::Pgs ? "pgs" : "soft-step";
        for (int step = 1; step <= 30; ++step) ASSERT_TRUE(w.step().ok()) << name;
        // The first step waits (no round before it to assume).
        for (int step = 31; step <= 60; ++step) {
            ASSERT_TRUE(w.step().ok()) << name;
            EXPECT_GT(w.lastStep().deviceContactCount, 100u) << name << ", step " << step;
            EXPECT_EQ(w.lastStep().deviceWaits, 0u) << name << ", step " << step;
        }
    }
}

// Three crates resting on the floor and a block of two layers of sixteen falling onto it: with
// room for 200 pairs the landing step finds more, after steps that ran ahead on room for all. That
// step runs again from its start (bodies, islands, the plan's levels, which the landing changes,
// pair sets), now waiting and with grown buffers, and the run ends on the bits of one with room
// from the start; so do the energy watch's sums and its lowest.
TEST_F(StepAhead, AnOverflowSeenLateStepsTheBitsOfARoomyRun) {
    // More than the falling block's pairs, fewer than the landed block's.
    constexpr std::uint32_t kTightPairs = 200;
    std::string json = R"({"format": "rubble-scene", "version": 1, "name": "landing",
      "simulation": {"dt": 0.016666667, "solver": {"type": "SOLVER", "iterations": 10}},
      "materials": {"default": {"friction": 0.5, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true})";
    for (int i = 0; i < 3; ++i)
        json += R"(, {"name": "rest)" + std::to_string(i) +
                R"(", "shape": "crate", "mass": 1, "position": [)" + std::to_string(-6 + 3 * i) +
                R"(, 0.5, -6]})";
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x)
            for (int z = 0; z < 4; ++z)
                json += R"(, {"name": "fall)" + std::to_string((y * 4 + x) * 4 + z) +
                        R"(", "shape": "crate", "mass": 1, "position": [)" +
                        std::to_string(x * 0.99) + ", " + std::to_string(1.5 + y) + ", " +
                        std::to_string(z * 0.99) + "]}";
    json += "]}";
    for (const char* solver : {"pgs", "soft-step"}) {
        std::string scene = json;
        scene.replace(scene.find("SOLVER"), 6, solver);
        test::StageInput in = test::stageInput(scene);
        std::vector<shared::BodyPose> poses[2];
        std::vector<shared::BodyVelocity> velocities[2];
        // The energy watch's sums each step and each body's energy at the lowest sum.
        std::vector<std::pair<float, float>> energies[2];
        std::vector<double> atLowest[2];
        int overflowStep = 0;
        for (int run = 0; run < 2; ++run) {
            gpu::PipelineInput input;
            input.bodies = in.bodies.view();
            input.surfaces = in.surfaces;
            input.collision = CollisionMethod::Sat;
            input.shapes = in.shapes;
            input.joined = in.joined;
            input.islands = true;
            input.pgsBlocks = 0;
            input.pgsColoring = PgsColoring::Device;
            input.pairCapacity = run == 0 ? kTightPairs : 0u;
            Result<gpu::PipelineHandle> made = gpu::Pipeline::create(context(), input);
            ASSERT_TRUE(made.ok()) << made.error().describe();
            gpu::Pipeline& p = **made;
            for (int step = 0; step < 90; ++step) {
                const StepParams params = in.params(step);
                StepStats stats;
                gpu::StepInputs inputs;
                inputs.sumEnergy = true;
                inputs.restartEnergy = step == 0;
                ::testing::internal::CaptureStderr();
                const Status begun = p.beginStep(params, inputs);
                const Status met = begun.ok() ? p.endStep(params, in.names, stats) : begun;
                const std::string said = ::testing::internal::GetCapturedStderr();
                ASSERT_TRUE(met.ok()) << solver << ": " << met.error().describe();
                if (run == 0 && said.find("pair overflow") != std::string::npos) {
                    EXPECT_EQ(overflowStep, 0) << solver << ": a second overflow";
                    overflowStep = step + 1;
                    EXPECT_GT(stats.deviceWaits, 0u) << solver; // the step ran again
                }
                const std::optional<std::pair<float, float>> e = p.energyOfLastStep();
                ASSERT_TRUE(e.has_value()) << solver << ", step " << step + 1;
                energies[run].push_back(*e);
            }
            ASSERT_TRUE(p.downloadLowestEnergies(atLowest[run]).ok());
            BodyArrays out = in.bodies;
            ASSERT_TRUE(p.downloadBodies(out.view()).ok());
            poses[run] = out.poses;
            velocities[run] = out.velocities;
        }
        // The overflow came in a step after the first, which ran ahead (the first waits).
        EXPECT_GT(overflowStep, 10) << solver;
        std::printf("[ %s ] pairs overflowed in step %d\n", solver, overflowStep);
        ASSERT_EQ(poses[0].size(), poses[1].size());
        for (std::size_t i = 0; i < poses[0].size(); ++i) {
            EXPECT_EQ(std::memcmp(&poses[0][i], &poses[1][i], sizeof(shared::BodyPose)), 0)
                << solver << ": " << in.names[i];
            EXPECT_EQ(
                std::memcmp(&velocities[0][i], &velocities[1][i], sizeof(shared::BodyVelocity)), 0)
                << solver << ": " << in.names[i];
        }
        ASSERT_EQ(energies[0].size(), energies[1].size());
        for (std::size_t i = 0; i < energies[0].size(); ++i) {
            EXPECT_EQ(energies[0][i].first, energies[1][i].first) << solver << ", step " << i + 1;
            EXPECT_EQ(energies[0][i].second, energies[1][i].second) << solver << ", step " << i + 1;
        }
        EXPECT_EQ(atLowest[0], atLowest[1]) << solver;
        // The block landed: the trajectory compared is not a free fall.
        EXPECT_LT(poses[1][in.bodies.count() - 1].position.y, 1.6f) << solver;
    }
}

} // namespace
} // namespace rubble
