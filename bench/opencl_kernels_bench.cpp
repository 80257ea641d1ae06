// bench/opencl_kernels_bench.cpp: each stage of the OpenCL pipeline on the first device (PoCL on
// the CPU in CI), on a debris pile stepped until it has contacts; bytes processed are the
// kernels' counted traffic (host/gpu/traffic.h), so the figures read as bytes/s. Flags before
// Google Benchmark's own: --scene=FILE (default scenes/bench/debris_16k.json), --steps=N (120),
// --spacing=M (0.5). The SAT method's kernels (benchSatKernel, one per kernel, device time from
// the profiling events) run on the same scene stepped on the CPU reference. Figures and
// commands are in docs/opencl.md.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "host/collision/sat_collision.h"
#include "host/core/math.h"
#include "host/core/step_params.h"
#include "host/gpu/hull_data.h"
#include "host/gpu/integrate.h"
#include "host/gpu/pipeline.h"
#include "host/gpu/traffic.h"
#include "rubble/scene.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/narrow_phase.h"
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
    std::unique_ptr<test::DeviceStage> stage;
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
    Result<std::unique_ptr<test::DeviceStage>> stage = test::deviceStage(*context, std::move(in));
    RUBBLE_TRY(stage);
    test::DeviceStage& p = **stage;
    RUBBLE_TRY(p.collision.transform(p.q(), p.bodies));
    RUBBLE_TRY(p.collision.buildGrid(p.q(), p.bodies, p.sort));
    RUBBLE_TRY(p.resetStatus());
    RUBBLE_TRY(p.collision.collide(p.q()));
    RUBBLE_TRY(p.collision.readCount(p.q()));
    b.stage = std::move(*stage);
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

test::DeviceStage* pipelineOrSkip(benchmark::State& state) {
    BenchWorld& b = benchWorld();
    if (!b.stage) {
        state.SkipWithError(b.error.c_str());
        return nullptr;
    }
    return b.stage.get();
}

gpu::TrafficCounts countsOf(const test::DeviceStage& p) {
    gpu::TrafficCounts n;
    n.bodies = p.bodies.count;
    n.particles = p.collision.count();
    n.cells = std::uint64_t(1) << p.collision.cellBits();
    n.contacts = p.collision.contacts().count;
    n.previous = 0;
    return n;
}

std::uint64_t bytesOf(const test::DeviceStage& p, std::initializer_list<gpu::KernelId> kernels,
                      int times = 1) {
    std::uint64_t sum = 0;
    for (gpu::KernelId k : kernels) sum += gpu::kernelBytes(k, countsOf(p));
    return sum * std::uint64_t(times);
}

// Runs `stage` and waits for it, once per iteration; reports its kernels' counted bytes.
template <class F>
void runStage(benchmark::State& state, test::DeviceStage& p, std::uint64_t bytes, F&& stage) {
    for (auto _ : state) {
        const Status s = stage();
        const Status done = p.finish();
        if (!s || !done) {
            state.SkipWithError((!s ? s : done).error().describe().c_str());
            return;
        }
    }
    state.SetBytesProcessed(std::int64_t(bytes) * state.iterations());
    state.counters["contacts"] = double(p.collision.contacts().count);
}

void benchTransformParticles(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::TransformParticles}),
             [&] { return p->collision.transform(p->q(), p->bodies); });
}

// Cell keys, the radix sort (five 4-bit passes of histogram, scan, scatter) and cell ranges.
void benchBuildGrid(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    const int passes =
        int((p->collision.cellBits() + RUBBLE_SORT_DIGIT_BITS - 1) / RUBBLE_SORT_DIGIT_BITS);
    const std::uint64_t bytes =
        bytesOf(*p, {gpu::KernelId::ComputeCellKeys, gpu::KernelId::FindCellRanges}) +
        bytesOf(*p, {gpu::KernelId::SortHistogram, gpu::KernelId::SortScatter}, passes);
    runStage(state, *p, bytes, [&] { return p->collision.buildGrid(p->q(), p->bodies, p->sort); });
}

// The radix sort alone, on a copy of the grid's sorted keys in reverse order.
void benchRadixSort(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    const gpu::Context& c = p->context();
    const std::uint32_t n = p->collision.count(), bits = p->collision.cellBits();
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
                 return p->sort.sort(p->q(), k, v, ka, va, n, bits);
             });
}

void benchCollideParticles(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    if (Status s = p->collision.buildGrid(p->q(), p->bodies, p->sort); !s) return state.SkipWithError(s.error().describe().c_str());
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::CollideParticles}), [&]() -> Status {
        RUBBLE_TRY(p->resetStatus());
        RUBBLE_TRY(p->collision.collide(p->q()));
        return p->collision.readCount(p->q());
    });
}

// Per-body lists, JacobiBody, rows (no warm start: last step's contacts are not kept here).
void benchBuildJacobiRows(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    const shared::SolverParams params = benchWorld().stage->in.params().rows;
    using K = gpu::KernelId;
    const std::uint64_t bytes =
        bytesOf(*p, {K::PrepareJacobiBodies, K::CountBodyContacts, K::FillBodyLists,
                     K::SortBodyLists, K::BuildJacobiRows});
    runStage(state, *p, bytes, [&] {
        return p->jacobi.buildRows(p->q(), p->bodies, p->collision.contacts(), p->collision.count(),
                                   params, false);
    });
}

// The Jacobi solve with range(0) sweeps: the first gather, range(0) x (rows, gather), absorb.
void benchSolveJacobi(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    const int sweeps = int(state.range(0));
    using K = gpu::KernelId;
    const std::uint64_t bytes = bytesOf(*p, {K::GatherJacobiRows, K::AbsorbVelocityChange}) +
                                bytesOf(*p, {K::SolveJacobiRows, K::GatherJacobi}, sweeps);
    runStage(state, *p, bytes, [&] {
        return p->jacobi.solve(p->q(), p->bodies, p->collision.contacts(), sweeps, 1.5f);
    });
}

void benchIntegrateVelocities(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::IntegrateVelocities}), [&] {
        return gpu::integrateVelocities(p->q(), p->bodies, shared::float4{0, 0, 0, 0}, 0.0f);
    });
}

void benchIntegratePositions(benchmark::State& state) {
    test::DeviceStage* p = pipelineOrSkip(state);
    if (!p) return;
    // dt = 0: the bodies stay where they are however often it runs.
    runStage(state, *p, bytesOf(*p, {gpu::KernelId::IntegratePositions}),
             [&] { return gpu::integratePositions(p->q(), p->bodies, 0.0f, true); });
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
    test::DeviceStage& p = *small.stage;
    const std::uint32_t stride = lcpStride(in.surfaces, in.bodies.masses);
    if (p.collision.contacts().count * stride > kLcpMaxRows)
        return state.SkipWithError("more than 4096 rows: the dense solver does not take them");
    const shared::SolverParams params = in.params().rows;
    if (Status st = p.jacobi.buildRows(p.q(), p.bodies, p.collision.contacts(),
                                       p.collision.count(), params, false);
        !st)
        return state.SkipWithError(st.error().describe().c_str());
    const int sweeps = int(state.range(0));
    for (auto _ : state) {
        const Status st =
            p.jacobi.solveDense(p.q(), p.bodies, p.collision.contacts(), stride, sweeps, 1.0f);
        const Status done = p.finish();
        if (!st || !done) return state.SkipWithError((!st ? st : done).error().describe().c_str());
    }
    // The Delassus matrix is read once per sweep (SGEMV): rows^2 floats.
    const double rows = double(p.collision.contacts().count) * stride;
    state.SetBytesProcessed(std::int64_t(rows * rows * 4.0 * sweeps) * state.iterations());
    state.counters["rows"] = rows;
}

// The SAT method on the same scene: stepped `steps` times on the CPU reference (sat, pgs), its
// state on two pipelines made for SAT whose pairs were found and collided once; "warm" also
// keeps those features, so that its narrow phase reuses them (the poses do not move), while
// "cold" runs the full test for every pair.
struct SatBenchWorld {
    std::optional<test::StageInput> in;
    std::unique_ptr<test::DeviceStage> cold, warm;
    gpu::TrafficCounts counts;
    std::string error;
};

Status prepareSat(const BenchSettings& settings, SatBenchWorld& b) {
    Result<Scene> scene = loadScene(settings.scene);
    RUBBLE_TRY(scene);
    scene->simulation.backend = Backend::Cpu;
    scene->simulation.collision.method = CollisionMethod::Sat;
    scene->simulation.solver.type = SolverType::Pgs;
    Result<World> world = World::create(*scene);
    RUBBLE_TRY(world);
    for (int i = 0; i < settings.steps; ++i) RUBBLE_TRY(world->step());
    Result<std::shared_ptr<gpu::Context>> context = openDevice(RunOptions{});
    RUBBLE_TRY(context);
    b.in.emplace(test::stageInput(*scene));
    test::takeState(*world, *b.in);
    const float dt = b.in->params().dt;
    for (std::unique_ptr<test::DeviceStage>* p : {&b.cold, &b.warm}) {
        Result<std::unique_ptr<test::DeviceStage>> made = test::satStage(*context, *b.in);
        RUBBLE_TRY(made);
        *p = std::move(*made);
        RUBBLE_TRY((*p)->resetStatus());
        RUBBLE_TRY((*p)->broadPhase(dt));
        Result<std::uint32_t> pairs = (*p)->readPairCount();
        RUBBLE_TRY(pairs);
        RUBBLE_TRY((*p)->narrowPhase(dt));
        RUBBLE_TRY((*p)->finish());
    }
    // The warm pipeline keeps its features and finds the same pairs again.
    RUBBLE_TRY(b.warm->keepPairFeatures());
    RUBBLE_TRY(b.warm->findPairs());
    RUBBLE_TRY(b.warm->narrowPhase(dt));
    Result<gpu::DeviceStatus> st = b.warm->readStatus();
    RUBBLE_TRY(st);
    gpu::TrafficCounts& n = b.counts;
    n.bodies = b.in->bodies.count();
    n.pairs = st->pairs;
    n.gridEntries = st->gridEntries;
    n.largeBodies = st->largeBodies;
    n.planes = b.warm->broad.planeCount();
    n.sortItems = b.warm->context().workSizes().sortItems;
    n.contacts = st->contacts;
    std::fprintf(stderr, "SAT bench: %u bodies, %u pairs, %u contacts, %u grid entries, %u large\n",
                 b.in->bodies.count(), st->pairs, st->contacts, st->gridEntries, st->largeBodies);
    for (test::DeviceStage* p : {b.cold.get(), b.warm.get()}) RUBBLE_TRY(p->collectProfile(n));
    return {};
}

BenchSettings& benchSettings() {
    static BenchSettings settings;
    return settings;
}

SatBenchWorld& satWorld() {
    static SatBenchWorld w = [] {
        SatBenchWorld b;
        if (Status s = prepareSat(benchSettings(), b); !s) b.error = s.error().describe();
        return b;
    }();
    return w;
}

// The device time of one kernel per iteration (profiling events; manual time), running the
// stage that launches it; bytes are the kernel's counted traffic. `warm` picks the pipeline that
// reuses its features. A fixed count of iterations: each runs the whole stage, however short
// the kernel.
void benchSatKernel(benchmark::State& state, gpu::KernelId kernel, bool warm) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    test::DeviceStage& p = warm ? *b.warm : *b.cold;
    const float dt = b.in->params().dt;
    auto deviceMs = [&] {
        for (const gpu::CommandTotals& t : p.profileTotals())
            if (t.name == gpu::signatureOf(kernel).name) return t.ms;
        return 0.0;
    };
    for (auto _ : state) {
        const double before = deviceMs();
        Status s = kernel == gpu::KernelId::ComputeAabbs    ? p.computeAabbs(dt)
                   : kernel == gpu::KernelId::CollideShapes ? p.narrowPhase(dt)
                                                            : p.findPairs();
        if (s) s = p.finish();
        if (s) s = p.collectProfile(b.counts).status();
        if (!s) return state.SkipWithError(s.error().describe().c_str());
        state.SetIterationTime((deviceMs() - before) * 1e-3);
    }
    state.SetBytesProcessed(std::int64_t(gpu::kernelBytes(kernel, b.counts)) * state.iterations());
    state.counters["pairs"] = double(b.counts.pairs);
    state.counters["MB"] = double(gpu::kernelBytes(kernel, b.counts)) * 1e-6;
}

// The whole stages, wall time: broadPhase (boxes, grid, sort, pairs) and narrowPhase.
void benchSatBroadPhase(benchmark::State& state) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    test::DeviceStage& p = *b.cold;
    const float dt = b.in->params().dt;
    for (auto _ : state) {
        Status s = p.broadPhase(dt);
        if (s) s = p.finish();
        if (s) s = p.collectProfile(b.counts).status();
        if (!s) return state.SkipWithError(s.error().describe().c_str());
    }
    state.counters["pairs"] = double(b.counts.pairs);
}

void benchSatNarrowPhase(benchmark::State& state) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    test::DeviceStage& p = state.range(0) ? *b.warm : *b.cold;
    const float dt = b.in->params().dt;
    for (auto _ : state) {
        Status s = p.narrowPhase(dt);
        if (s) s = p.finish();
        if (s) s = p.collectProfile(b.counts).status();
        if (!s) return state.SkipWithError(s.error().describe().c_str());
    }
    state.counters["pairs"] = double(b.counts.pairs);
    state.counters["contacts"] = double(b.counts.contacts);
}

// The CPU reference on the same state, for the ratio: SatCollision's broadPhase, and its
// narrowPhase with an empty cache (range 0: every pair runs the full test) or with the features
// of a first run kept (range 1).
void benchCpuSatBroadPhase(benchmark::State& state) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    SatCollision cpu(ContactForm::Manifolds);
    StepContacts out;
    const StepParams params = b.in->params();
    for (auto _ : state)
        if (!cpu.broadPhase(b.in->collisionScene(), b.in->bodies.view(), params, out).ok())
            return state.SkipWithError("the broad phase failed");
    state.counters["pairs"] = double(out.pairs.size());
}

void benchCpuSatNarrowPhase(benchmark::State& state) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    SatCollision warm(ContactForm::Manifolds);
    StepContacts out;
    const StepParams params = b.in->params();
    const CollisionScene scene = b.in->collisionScene();
    if (!warm.broadPhase(scene, b.in->bodies.view(), params, out).ok() ||
        !warm.narrowPhase(scene, b.in->bodies.view(), params, out).ok())
        return state.SkipWithError("the collision stages failed");
    for (auto _ : state) {
        if (state.range(0)) {
            if (!warm.narrowPhase(scene, b.in->bodies.view(), params, out).ok())
                return state.SkipWithError("the narrow phase failed");
            continue;
        }
        state.PauseTiming();
        SatCollision cold(ContactForm::Manifolds);
        const bool found = cold.broadPhase(scene, b.in->bodies.view(), params, out).ok();
        state.ResumeTiming();
        if (!found || !cold.narrowPhase(scene, b.in->bodies.view(), params, out).ok())
            return state.SkipWithError("the collision stages failed");
    }
    state.counters["pairs"] = double(out.pairs.size());
    state.counters["contacts"] = double(out.contactCount);
}

// The pair summaries of the pipeline that kept its features, and the status read after them, as
// colorPgs expects them.
Status summarizeWarm(SatBenchWorld& b) {
    RUBBLE_TRY(b.warm->summarizePairs(b.in->params()));
    return b.warm->readStatus().status();
}

// The host's part of the device's PGS step, wall time: colorPgs (the pair summaries and pairs
// read back, the coloring by support, the elements and build order written), after one
// summarizePairs on the pipeline that kept its features.
void benchSatColoring(benchmark::State& state) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    test::DeviceStage& p = *b.warm;
    Status s = summarizeWarm(b);
    for (auto _ : state) {
        if (s) s = p.colorPgs();
        if (s) s = p.finish();
        if (!s) return state.SkipWithError(s.error().describe().c_str());
    }
    state.counters["pairs"] = double(b.counts.pairs);
    state.counters["elements"] = double(p.pgs.elements().size());
    // How many colors, and the largest and smallest color's elements.
    const gpu::Coloring& coloring = p.pgs.coloring();
    const std::span<const std::uint32_t> start = coloring.start();
    state.counters["colors"] = double(coloring.colors());
    std::uint32_t largest = 0, smallest = ~0u;
    for (std::uint32_t k = 0; k < coloring.colors(); ++k) {
        largest = std::max(largest, start[k + 1] - start[k]);
        smallest = std::min(smallest, start[k + 1] - start[k]);
    }
    if (coloring.colors() > 0) {
        state.counters["largest"] = double(largest);
        state.counters["smallest"] = double(smallest);
    }
}

// The coloring itself, without the transfers around it: Coloring::addBySupport and finish over
// the elements colorPgs listed (the pairs with rows of the same step as benchSatColoring).
void benchSatColoringOnHost(benchmark::State& state) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    test::DeviceStage& p = *b.warm;
    Status s = summarizeWarm(b);
    if (s) s = p.colorPgs();
    if (s) s = p.finish();
    if (!s) return state.SkipWithError(s.error().describe().c_str());
    // Every pair with rows colored (as a GPU colors them; a CPU device colors only the few
    // between its blocks). debris_16k has no joints: the elements are the pairs.
    const std::vector<gpu::ColorElement> elements(p.pgs.stepElements().begin(),
                                                   p.pgs.stepElements().end());
    gpu::Coloring coloring;
    for (auto _ : state) {
        coloring.begin(b.in->bodies.count());
        coloring.addBySupport(elements);
        coloring.finish();
        benchmark::DoNotOptimize(coloring.colors());
    }
    state.counters["elements"] = double(elements.size());
    state.counters["colors"] = double(coloring.colors());
}

// The device's narrow phase code (rubble/shared/narrow_phase.h) compiled for the host, on the
// same pairs, one thread, with an empty cache (range 0) or last run's (range 1): how much of
// the kernel's time is the code and how much the OpenCL compiler and runtime.
void benchSharedNarrowPhaseOnHost(benchmark::State& state) {
    SatBenchWorld& b = satWorld();
    if (!b.in) return state.SkipWithError(b.error.c_str());
    Result<std::vector<BodyPair>> pairs = b.cold->downloadPairs();
    Result<gpu::HullData> hulls = gpu::flattenShapes(b.in->shapes);
    if (!pairs || !hulls) return state.SkipWithError("pairs or hulls");
    const shared::HullArrays arrays = gpu::hullArraysOf(*hulls);
    const BodyArrays& bodies = b.in->bodies;
    const float dt = b.in->params().dt;
    std::vector<shared::PairCache> caches(pairs->size(), shared::emptyPairCacheItem());
    std::uint32_t contacts = 0;
    auto run = [&] {
        contacts = 0;
        for (std::size_t i = 0; i < pairs->size(); ++i) {
            const BodyPair pair = (*pairs)[i];
            if (!state.range(0)) caches[i] = shared::emptyPairCacheItem();
            const shared::BodyVelocity va = bodies.velocities[pair.a],
                                       vb = bodies.velocities[pair.b];
            const float spinA =
                shared::spinItem(va, hulls->shapes[bodies.shapeOf[pair.a]].boundingRadius, dt);
            const float spinB =
                shared::spinItem(vb, hulls->shapes[bodies.shapeOf[pair.b]].boundingRadius, dt);
            const shared::ContactManifold m =
                shared::collideShapesItem(arrays, hulls->shapes[bodies.shapeOf[pair.a]],
                                          shared::transformOfPose(bodies.poses[pair.a]),
                                          hulls->shapes[bodies.shapeOf[pair.b]],
                                          shared::transformOfPose(bodies.poses[pair.b]), &caches[i],
                                          shared::pairMarginItem(va, vb, spinA, spinB, dt));
            contacts += m.count;
        }
    };
    run();
    for (auto _ : state) run();
    state.counters["pairs"] = double(pairs->size());
    state.counters["contacts"] = double(contacts);
}

} // namespace
} // namespace rubble

BENCHMARK(rubble::benchSharedNarrowPhaseOnHost)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(rubble::benchCpuSatBroadPhase)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchCpuSatNarrowPhase)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

using rubble::benchSatKernel;
#define RUBBLE_SAT_KERNEL(kernel, warm)                                                            \
    BENCHMARK_CAPTURE(benchSatKernel, kernel, rubble::gpu::KernelId::kernel, warm)                 \
        ->Unit(benchmark::kMillisecond)                                                            \
        ->Iterations(30)                                                                           \
        ->UseManualTime()
RUBBLE_SAT_KERNEL(ComputeAabbs, false);
RUBBLE_SAT_KERNEL(GridBounds, false);
RUBBLE_SAT_KERNEL(GridSetup, false);
RUBBLE_SAT_KERNEL(GridEntries, false);
RUBBLE_SAT_KERNEL(GatherCellBoxes, false);
RUBBLE_SAT_KERNEL(FindCellPairs, false);
RUBBLE_SAT_KERNEL(FindLargePairs, false);
RUBBLE_SAT_KERNEL(CountPairs, false);
RUBBLE_SAT_KERNEL(PlacePairs, false);
RUBBLE_SAT_KERNEL(SortPairLists, false);
RUBBLE_SAT_KERNEL(CollideShapes, false);
BENCHMARK_CAPTURE(benchSatKernel, CollideShapesCached, rubble::gpu::KernelId::CollideShapes, true)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(30)
    ->UseManualTime();
BENCHMARK(rubble::benchSatBroadPhase)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchSatNarrowPhase)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(rubble::benchSatColoring)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(rubble::benchSatColoringOnHost)->Unit(benchmark::kMillisecond)->UseRealTime();

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
    rubble::BenchSettings& settings = rubble::benchSettings();
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
