// tests/gpu/gpu_fixture.h: one OpenCL context (device, program, kernels) for the whole gpu test
// binary, so that the program is built once; worlds put on it, and float comparisons.
#pragma once

#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include "host/gpu/context.h"
#include "host/gpu/pipeline.h"
#include "support/device_stage.h"
#include "support/test_util.h"

namespace rubble::test {

/// The binary's context, created on first use; null when it could not be (the error is kept).
struct SharedGpu {
    std::shared_ptr<gpu::Context> context;
    std::optional<Error> error;
};

inline SharedGpu& sharedGpu() {
    static SharedGpu gpu = [] {
        SharedGpu g;
        Result<std::shared_ptr<gpu::Context>> c = openDevice(RunOptions{});
        if (c) g.context = *c;
        else g.error = c.error();
        return g;
    }();
    return gpu;
}

/// Skips when no OpenCL platform exists and CI is unset; in CI that is a failure.
class GpuTest : public ::testing::Test {
  protected:
    void SetUp() override {
        SharedGpu& g = sharedGpu();
        if (g.context) return;
        const bool noPlatform = g.error->kind == ErrorKind::NotSupported;
        if (noPlatform && std::getenv("CI") == nullptr)
            GTEST_SKIP() << "no OpenCL platform (and CI is unset): " << g.error->describe();
        FAIL() << "no OpenCL context: " << g.error->describe();
    }
    const std::shared_ptr<gpu::Context>& context() { return sharedGpu().context; }

    /// A world from scene text on the shared device (the scene's backend set to opencl), as
    /// World::create puts it there: the debris set (or the bodies without joints) on the
    /// device, the other bodies in a CPU world of their own.
    World deviceWorld(const std::string& json, bool deterministic = false) {
        RunOptions run;
        run.deterministic = deterministic;
        return deviceWorld(json, run);
    }
    World deviceWorld(const std::string& json, const RunOptions& run) {
        Scene scene = sceneOf(json);
        scene.simulation.backend = Backend::OpenCl;
        return worldOf(scene, run);
    }
    /// SAT with each body sleeping by itself on the device (RunOptions::bodySleep) instead of
    /// by islands: the body-sleep kernels of kernels/sleep.cl on the SAT path.
    World bodySleepWorld(const std::string& json) {
        RunOptions run;
        run.bodySleep = true;
        return deviceWorld(json, run);
    }

    /// The scene of `json` (aborts the test binary when it does not parse).
    static Scene sceneOf(const std::string& json) {
        Result<Scene> scene = parseScene(json, "inline.json", ".");
        EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
        if (!scene.ok()) std::abort();
        return std::move(*scene);
    }

    /// A world of `scene` with `run` on the shared device (aborts when it cannot be made).
    World worldOf(const Scene& scene, RunOptions run = {}) {
        run.context = context();
        Result<World> w = World::create(scene, run);
        EXPECT_TRUE(w.ok()) << (w.ok() ? "" : w.error().describe());
        if (!w.ok()) std::abort();
        return std::move(*w);
    }

    /// ... stepping `backend` with `method` and `solver`, the device's PGS in `blocks`
    /// (RunOptions::pgsBlocks: -1 as the device suits, 0 every element colored).
    World worldOf(Scene scene, Backend backend, CollisionMethod method, SolverType solver,
                  int blocks = -1) {
        scene.simulation.backend = backend;
        scene.simulation.collision.method = method;
        scene.simulation.solver.type = solver;
        RunOptions run;
        run.pgsBlocks = blocks;
        return worldOf(scene, run);
    }

    /// A stage input from scene text, taken from `world` (built from the same text) when given,
    /// with the particle method's stages of its own on the shared device.
    std::unique_ptr<DeviceStage> deviceStage(const std::string& json,
                                             const World* world = nullptr) {
        StageInput in = stageInput(json);
        if (world) takeState(*world, in);
        return made(test::deviceStage(context(), std::move(in)));
    }
    /// ... with the SAT method's stages, its PGS in `pgsBlocks` blocks.
    std::unique_ptr<DeviceStage> satStage(StageInput in, int pgsBlocks = -1,
                                          bool deviceColoring = false) {
        return made(test::satStage(context(), std::move(in), pgsBlocks, deviceColoring));
    }

  private:
    static std::unique_ptr<DeviceStage> made(Result<std::unique_ptr<DeviceStage>> d) {
        EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().describe());
        if (!d.ok()) std::abort();
        return std::move(*d);
    }
};

/// |a - b| <= tol * max(1, |a|, |b|), component by component.
inline ::testing::AssertionResult nearRel(float a, float b, float tol) {
    const float scale = std::max(1.0f, std::max(std::fabs(a), std::fabs(b)));
    if (std::fabs(a - b) <= tol * scale) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a << " vs " << b << " (tolerance " << tol * scale << ")";
}

/// Compares two arrays of float records (float4 fields and floats) as flat floats.
template <class T>
void expectNearRel(std::span<const T> a, std::span<const T> b, float tol) {
    static_assert(sizeof(T) % sizeof(float) == 0);
    ASSERT_EQ(a.size(), b.size());
    const float* x = reinterpret_cast<const float*>(a.data());
    const float* y = reinterpret_cast<const float*>(b.data());
    const std::size_t n = a.size_bytes() / sizeof(float), per = sizeof(T) / sizeof(float);
    int failures = 0;
    for (std::size_t i = 0; i < n && failures < 10; ++i) {
        const ::testing::AssertionResult r = nearRel(x[i], y[i], tol);
        if (!r) {
            ADD_FAILURE() << "element " << i / per << ", float " << i % per << ": " << r.message();
            ++failures;
        }
    }
}
template <class T>
void expectNearRel(const std::vector<T>& a, const std::vector<T>& b, float tol) {
    expectNearRel(std::span<const T>(a), std::span<const T>(b), tol);
}

/// A world's device commands over the run by name (World::deviceProfile); a command never run
/// reads as zeros.
inline std::map<std::string, DeviceCommandTime> deviceProfileByName(const World& w) {
    std::map<std::string, DeviceCommandTime> out;
    for (const DeviceCommandTime& c : w.deviceProfile()) out[c.name] = c;
    return out;
}

/// Whether two bodies' states (position, orientation, velocities) are the same to the bit.
inline bool sameBits(const BodyState& a, const BodyState& b) {
    return std::memcmp(&a.position, &b.position, sizeof a.position) == 0 &&
           std::memcmp(&a.orientation, &b.orientation, sizeof a.orientation) == 0 &&
           std::memcmp(&a.linearVelocity, &b.linearVelocity, sizeof a.linearVelocity) == 0 &&
           std::memcmp(&a.angularVelocity, &b.angularVelocity, sizeof a.angularVelocity) == 0;
}

} // namespace rubble::test
