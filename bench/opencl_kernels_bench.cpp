// bench/opencl_kernels_bench.cpp: each stage of the OpenCL pipeline on the first device (PoCL on
// the CPU in CI), on a debris pile stepped until it has contacts; bytes processed are the
// kernels' counted traffic (host/gpu/traffic.h), so the figures read as bytes/s. Flags before
// Google Benchmark's own: --scene=FILE (default scenes/bench/debris_16k.json), --steps=N (120),
// --spacing=M (0.5). Figures and commands are in docs/opencl.md.
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "host/core/math.h"
#include "host/core/step_params.h"
#include "host/gpu/pipeline.h"
#include "host/gpu/traffic.h"
#include "rubble/scene.h"
#include "rubble/world.h"
#include "support/device_stage.h"

namespace rubble {
namespace {

struct BenchSettings {
    std::string scene = RUBBLE_SOURCE_DIR "/scenes/bench/debris_16k.json";
    int steps = 120;
    float spacing = 0.5f;
};

// A scene on the device stepped `steps` times, then its state on a pipeline of its own whose
// contacts are collided once: what every benchmark of that scene works on.
struct BenchWorld {
    std::optional<test::DeviceStage> stage;
    std::string error;
};

Status prepare(const std::string& path, float spacing, int steps, BenchWorld& b) {
    Result<Scene> scene = loadScene(path);
    RUBBLE_TRY(scene);
    scene->simulation.backend = Backend::OpenCl;
    scene->simulation.collision.method = CollisionMethod::Particles;
    scene->simulation.collision.particleSpacing = spacing;
    scene->simulation.solver.type = SolverType::Jacobi;
    Result<std::shared_ptr<gpu::Context>> context = openDevice(RunOptions{});
    RUBBLE_TRY(context);
    RunOptions run;
    run.context = *context;
    Result<World> world = World::create(*scene, run);
    RUBBLE_TRY(world);
    for (int i = 0; i < steps; ++i) RUBBLE_TRY(world->step());
    test::StageInput in = test::stageInput(*scene);
    test::takeState(*world, in);
    Result<test::DeviceStage> stage = test::deviceStage(*context, std::move(in));
    RUBBLE_TRY(stage);
    gpu::Pipeline& p = stage->device();
    RUBBLE_TRY(p.transformParticles());
    RUBBLE_TRY(p.buildGrid());
    RUBBLE_TRY(p.resetStatus());
    RUBBLE_TRY(p.collideParticles());
    RUBBLE_TRY(p.readContactCount());
    b.stage.emplace(std::move(*stage));
    return {};
}

BenchWorld& benchWorld(const BenchSettings* settings = nullptr) {
    static BenchWorld w = [&] {
        BenchWorld b;
        if (Status s = prepare(settings->scene, settings->spacing, settings->steps, b); !s)
            b.error = s.error().describe();
        return b;
    }();
    return w;
}

gpu::Pipeline* pipelineOrSkip(benchmark::State& state) {
    BenchWorld& b = benchWorld();
    if (!b.stage) {
        state.SkipWithError(b.error.c_str());
        return nullptr;
    }
    return &b.stage->device();
}

gpu::TrafficCounts countsOf(const gpu::Pipeline& p) {
    gpu::TrafficCounts n;
    n.bodies = p.bodies().count;
    n.particles = p.particles().count;
    n.cells = std::uint64_t(1) << p.particles().bits;
    n.contacts = p.contacts().count;
    n.previous = 0;
    return n;
}

std::uint64_t bytesOf(const gpu::Pipeline& p, std::initializer_list<gpu::KernelId> kernels,
                      int times = 1) {
    std::uint64_t sum = 0;
    for (gpu::KernelId k : kernels) sum += gpu::kernelBytes(k, countsOf(p));
    return sum * std::uint64_t(times);
}

// Runs `stage` and waits for it, once per iteration; reports its kernels' counted bytes.
template <class F>
void runStage(benchmark::State& state, gpu::Pipeline& p, std::uint64_t bytes, F&& stage) {
    for (auto _ : state) {
        const Status s = stage();
        const Status done = p.finish();
        if (!s || !done) {
            state.SkipWithError((!s ? s : done).error().describe().c_str());
            return;
        }
    }
    state.SetBytesProcessed(std::int64_t(bytes) * state.iterations());
    state.counters["contacts"] = double(p.contacts().count);
}

void benchTransformParticles(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::TransformParticles}),
             [&] { return p->transformParticles(); });
}

// Cell keys, the radix sort (five 4-bit passes of histogram, scan, scatter) and cell ranges.
void benchBuildGrid(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    const int passes =
        int((p->particles().bits + RUBBLE_SORT_DIGIT_BITS - 1) / RUBBLE_SORT_DIGIT_BITS);
    const std::uint64_t bytes =
        bytesOf(*p, {gpu::KernelId::ComputeCellKeys, gpu::KernelId::FindCellRanges}) +
        bytesOf(*p, {gpu::KernelId::SortHistogram, gpu::KernelId::SortScatter}, passes);
    runStage(state, *p, bytes, [&] { return p->buildGrid(); });
}

// The radix sort alone, on a copy of the grid's sorted keys in reverse order.
void benchRadixSort(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    const gpu::Context& c = p->context();
    const std::uint32_t n = p->particles().count, bits = p->particles().bits;
    std::vector<std::uint32_t> keys(n), values(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        keys[i] = std::uint32_t((std::uint64_t(n - i) << bits) / (n + 1u));
        values[i] = i;
    }
    gpu::Buffer k, v, ka, va;
    if (!gpu::upload(c, k, std::span<const std::uint32_t>(keys)) ||
        !gpu::upload(c, v, std::span<const std::uint32_t>(values)) ||
        !ka.reserve(c.context(), n * sizeof(std::uint32_t)) ||
        !va.reserve(c.context(), n * sizeof(std::uint32_t))) {
        state.SkipWithError("radix sort buffers");
        return;
    }
    const int passes = int((bits + RUBBLE_SORT_DIGIT_BITS - 1) / RUBBLE_SORT_DIGIT_BITS);
    runStage(state, *p,
             bytesOf(*p, {gpu::KernelId::SortHistogram, gpu::KernelId::SortScatter}, passes), [&] {
                 // Sorted output goes to the Alt buffers and is swapped back in: the next
                 // iteration sorts sorted keys, which costs the same.
                 return p->radixSort(k, v, ka, va, n, bits, RUBBLE_STATUS_COUNT);
             });
}

void benchCollideParticles(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    if (Status s = p->buildGrid(); !s) return state.SkipWithError(s.error().describe().c_str());
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::CollideParticles}), [&]() -> Status {
        RUBBLE_TRY(p->resetStatus());
        RUBBLE_TRY(p->collideParticles());
        return p->readContactCount();
    });
}

// Per-body lists, JacobiBody, rows (no warm start: last step's contacts are not kept here).
void benchBuildJacobiRows(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    const shared::SolverParams params = benchWorld().stage->in.params().rows;
    using K = gpu::KernelId;
    const std::uint64_t bytes =
        bytesOf(*p, {K::PrepareJacobiBodies, K::CountBodyContacts, K::FillBodyLists,
                     K::SortBodyLists, K::BuildJacobiRows});
    runStage(state, *p, bytes, [&] { return p->buildJacobiRows(params, false); });
}

// The Jacobi solve with range(0) sweeps: the first gather, range(0) x (rows, gather), absorb.
void benchSolveJacobi(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    const int sweeps = int(state.range(0));
    using K = gpu::KernelId;
    const std::uint64_t bytes = bytesOf(*p, {K::GatherJacobiRows, K::AbsorbVelocityChange}) +
                                bytesOf(*p, {K::SolveJacobiRows, K::GatherJacobi}, sweeps);
    runStage(state, *p, bytes, [&] { return p->solveJacobi(sweeps, 1.5f, false); });
}

void benchIntegrateVelocities(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::IntegrateVelocities}), [&] {
        return p->integrateVelocities(shared::float4{0, 0, 0, 0}, 0.0f);
    });
}

void benchIntegratePositions(benchmark::State& state) {
    gpu::Pipeline* p = pipelineOrSkip(state);
    if (!p) return;
    // dt = 0: the bodies stay where they are however often it runs.
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::IntegratePositions}),
             [&] { return p->integratePositions(0.0f, true); });
}

// lcp-jacobi on its own small world (the pyramid of 20, settled for 30 steps): the dense
// solver takes at most 4096 rows.
void benchSolveLcpJacobi(benchmark::State& state) {
    static BenchWorld small;
    if (!small.stage && small.error.empty())
        if (Status s = prepare(RUBBLE_SOURCE_DIR "/scenes/pyramid_20.json", 0.5f, 30, small); !s)
            small.error = s.error().describe();
    if (!small.stage) return state.SkipWithError(small.error.c_str());
    const test::StageInput& in = small.stage->in;
    gpu::Pipeline& p = small.stage->device();
    const std::uint32_t stride = lcpStride(in.surfaces, in.bodies.masses);
    if (p.contacts().count * stride > kLcpMaxRows)
        return state.SkipWithError("more than 4096 rows: the dense solver does not take them");
    const shared::SolverParams params = in.params().rows;
    if (Status st = p.buildJacobiRows(params, false); !st)
        return state.SkipWithError(st.error().describe().c_str());
    const int sweeps = int(state.range(0));
    for (auto _ : state) {
        const Status st = p.solveLcpJacobi(stride, sweeps, 1.0f);
        const Status done = p.finish();
        if (!st || !done) return state.SkipWithError((!st ? st : done).error().describe().c_str());
    }
    // The Delassus matrix is read once per sweep (SGEMV): rows^2 floats.
    const double rows = double(p.contacts().count) * stride;
    state.SetBytesProcessed(std::int64_t(rows * rows * 4.0 * sweeps) * state.iterations());
    state.counters["rows"] = rows;
}

} // namespace
} // namespace rubble

BENCHMARK(rubble::benchTransformParticles)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchBuildGrid)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchRadixSort)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchCollideParticles)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchBuildJacobiRows)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchSolveJacobi)->Arg(1)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchIntegrateVelocities)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchIntegratePositions)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchSolveLcpJacobi)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
    rubble::BenchSettings settings;
    std::vector<char*> rest{argv[0]};
    for (int i = 1; i < argc; ++i) {
        const std::string_view a = argv[i];
        if (a.starts_with("--scene="))
            settings.scene = std::string(a.substr(8));
        else if (a.starts_with("--steps="))
            settings.steps = std::atoi(argv[i] + 8);
        else if (a.starts_with("--spacing="))
            settings.spacing = float(std::atof(argv[i] + 10));
        else
            rest.push_back(argv[i]);
    }
    int n = int(rest.size());
    benchmark::Initialize(&n, rest.data());
    if (benchmark::ReportUnrecognizedArguments(n, rest.data())) return 1;
    rubble::benchWorld(&settings);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
