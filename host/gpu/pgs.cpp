// host/gpu/pgs.cpp: dispatch of projected Gauss-Seidel on the device (kernels/pgs.cl): the rows
// of each pair's manifold, the host's split of the step's elements into blocks (a CPU device)
// and colors, then warm start, velocity sweeps and the split position pass, one launch for the
// blocks and one per color, and the pushes after integratePositions. The CPU twin is PgsSolver
// (host/dynamics/pgs_solver.cpp).
#include <algorithm>

#include "host/core/assert.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {
namespace {

// Bytes one launch of a sweep kernel moves for a color of `elements` elements with `points`
// rows: each element's record, both bodies' velocities read and written, and per point its
// rows (`rowBytes`) and its impulses read and written.
std::uint64_t sweepBytes(std::uint64_t elements, std::uint64_t points, std::uint64_t rowBytes) {
    constexpr std::uint64_t kVelocity = sizeof(shared::BodyVelocity);
    return elements * (sizeof(shared::PgsElement) + 4 * kVelocity) +
           points * (rowBytes + 2 * sizeof(shared::float4));
}

// Reserves `bytes` of a per-step buffer with room to grow: half as much again (at least 4 KiB),
// so that a pile that gains rows step by step reallocates now and then, not every step. (Oclgrind
// 21.10 also sees a buffer that replaces one the last step's commands used as never written,
// and reports every read of it: the small scenes it checks then reallocate nothing.)
Status reserveGrowing(const Context& c, Buffer& b, std::size_t bytes) {
    if (b.bytes() >= bytes) return {};
    return b.reserve(c.context(), std::max<std::size_t>(bytes + bytes / 2, 4096));
}

// A sweep kernel's launch (a color, the serial tail or the blocks), its first arguments bound:
// the launch's first element, count and mode, the step's elements and the blocks' starts.
Dispatch sweepLaunch(const Context& c, KernelId id, const PgsLaunch& l, const PgsBuffers& g,
                     Profile* profile) {
    Dispatch d(c, id, profile);
    d.arg(l.first).arg(l.count).arg(l.mode).arg(g.elements).arg(g.blockStarts);
    return d;
}

} // namespace

void Pipeline::bindPairs(Dispatch& d) const {
    const cl_uint capacity = sat_.current.capacity;
    d.arg(capacity).arg(sat_.current.count).arg(sat_.current.pairs);
}

void Pipeline::bindPreviousPairs(Dispatch& d) const {
    const cl_uint capacity = sat_.previous.capacity;
    d.arg(capacity).arg(sat_.previous.count).arg(sat_.previous.pairs);
}

void Pipeline::bindRowSettings(Dispatch& d, const StepParams& params) const {
    const SolverOptions& o = params.solver;
    const cl_float baumgarte = o.baumgarte, slop = o.slop, dt = params.dt;
    const cl_uint warm = o.warmStart ? 1u : 0u, previousCapacity = sat_.previous.capacity;
    d.arg(baumgarte)
        .arg(slop)
        .arg(dt)
        .arg(warm)
        .arg(previousCapacity)
        .arg(sat_.previous.count)
        .arg(sat_.previousOf)
        .arg(sat_.previous.impulseCount)
        .arg(sat_.previous.impulses);
}

Status Pipeline::summarizePairs(const StepParams& params) {
    RUBBLE_ASSERT(pairPgs());
    const Context& c = *context_;
    pgs_.summariesOnHost = false;
    RUBBLE_TRY(prepareJacobiBodies());
    RUBBLE_TRY(fill(c, pgs_.pushed, 0u, std::size_t(bodies_.count) * sizeof(cl_uint), &profile_));
    // The marks of this round of the collision (a pair overflow runs it again).
    RUBBLE_TRY(fillRange(c, status_, 0u, RUBBLE_STATUS_PUSHED * sizeof(cl_uint), sizeof(cl_uint),
                         &profile_));
    RUBBLE_TRY(fillRange(c, status_, 0u, RUBBLE_STATUS_BOUNCES * sizeof(cl_uint),
                         2 * sizeof(cl_uint), &profile_));
    RUBBLE_TRY(Dispatch(c, KernelId::SummarizePairs, &profile_)
                   .with([&](Dispatch& d) { bindPairs(d); })
                   .arg(sat_.manifolds)
                   .arg(bodies_.jacobi)
                   .arg(bodies_.poses)
                   .arg(bodies_.velocities)
                   .arg(bodies_.atStart)
                   .arg(contacts_.surfaces)
                   .with([&](Dispatch& d) { bindRowSettings(d, params); })
                   .arg(pgs_.pairRows)
                   .arg(sat_.current.impulseCount)
                   .arg(sat_.current.impulses)
                   .arg(pgs_.pushed)
                   .arg(status_)
                   .run(pairStrideItems(), c.workSizes().pairGroup));
    if (pgs_.jointCount == 0) return {};
    const cl_uint joints = pgs_.jointCount, warm = params.solver.warmStart ? 1u : 0u;
    const cl_float dt = params.dt;
    return Dispatch(c, KernelId::PrepareJoints, &profile_)
        .arg(joints)
        .arg(pgs_.joints)
        .arg(bodies_.poses)
        .arg(bodies_.jacobi)
        .arg(warm)
        .arg(dt)
        .arg(pgs_.jointRows)
        .run(joints, RUBBLE_GROUP_BODIES);
}

Status Pipeline::readPairSummaries() {
    PgsBuffers& g = pgs_;
    if (g.summariesOnHost) return {};
    const Context& c = *context_;
    // The status block was read after the summaries (readStatus waited for them).
    const std::uint32_t pairs = std::min(statusFromSlots().pairs, sat_.current.capacity);
    g.pairRowsHost.resize(pairs);
    g.pairsHost.resize(pairs);
    // Both reads queued, then one wait.
    RUBBLE_TRY(enqueueDownload(c, g.pairRows, std::span(g.pairRowsHost), &profile_));
    RUBBLE_TRY(download(c, sat_.current.pairs, std::span(g.pairsHost), &profile_));
    g.summariesOnHost = true;
    return {};
}

Status Pipeline::colorPgs() {
    const Context& c = *context_;
    PgsBuffers& g = pgs_;
    // The device idles from here until the coloring's upload.
    RUBBLE_TRY(readPairSummaries());
    const std::uint32_t pairs = std::uint32_t(g.pairsHost.size());
    // The elements: the joints first (the CPU's sweep solves them before the contacts), then the
    // pairs with rows in pair order.
    g.stepElements.clear();
    for (std::uint32_t j = 0; j < g.jointCount; ++j)
        g.stepElements.push_back({RUBBLE_PGS_JOINT_ELEMENT | j, g.jointsHost[j].a,
                                     g.jointsHost[j].b, g.jointDynamicA[j] != 0,
                                     g.jointDynamicB[j] != 0});
    for (std::uint32_t p = 0; p < pairs; ++p) {
        const cl_uint summary = g.pairRowsHost[p];
        if ((summary & RUBBLE_PGS_POINTS) == 0) continue;
        g.stepElements.push_back({p, g.pairsHost[p].a, g.pairsHost[p].b,
                                     (summary & RUBBLE_PGS_MOVES_A) != 0,
                                     (summary & RUBBLE_PGS_MOVES_B) != 0});
    }
    const std::span<const ColorElement> all(g.stepElements);
    // Blocks (a CPU device): the bodies cut into ranges of indices, an element whose moving
    // bodies are all in one range goes to that range's block, in the order above; a block runs
    // in order on one work-item, as the CPU's sweep does (docs/opencl.md, "Blocks"). The rest,
    // between blocks, and every element on a GPU, are colored.
    const std::uint32_t blocks = pgsBlocks_, bodies = bodies_.count;
    constexpr std::uint32_t kColored = 0xffffffffu;
    auto blockOf = [&](const ColorElement& x) {
        auto of = [&](std::uint32_t body) {
            return std::uint32_t(std::uint64_t(body) * blocks / std::max(bodies, 1u));
        };
        if (blocks == 0 || (!x.movesA && !x.movesB)) return kColored;
        if (x.movesA && x.movesB) return of(x.a) == of(x.b) ? of(x.a) : kColored;
        return of(x.movesA ? x.a : x.b);
    };
    // A counting sort by block, stable: each block's elements in the order above.
    g.blockOfHost.resize(all.size());
    g.blockStartsHost.assign(std::size_t(blocks) + 1, 0);
    g.coloredHost.clear();
    for (std::uint32_t k = 0; k < all.size(); ++k) {
        const std::uint32_t b = g.blockOfHost[k] = blockOf(all[k]);
        if (b == kColored)
            g.coloredHost.push_back(k);
        else
            ++g.blockStartsHost[b + 1];
    }
    for (std::uint32_t b = 0; b < blocks; ++b) g.blockStartsHost[b + 1] += g.blockStartsHost[b];
    const std::uint32_t inBlocks = g.blockStartsHost[blocks];
    // Where each element goes: its block's next place, or (below) its place among the colors
    // after the blocks.
    g.placeHost.resize(all.size());
    g.nextHost.assign(g.blockStartsHost.begin(), g.blockStartsHost.end());
    for (std::uint32_t k = 0; k < all.size(); ++k)
        if (g.blockOfHost[k] != kColored) g.placeHost[k] = g.nextHost[g.blockOfHost[k]]++;
    // The colored elements: greedy, joints one by one, the pairs from the bottom up
    // (Coloring::addBySupport), each color in pair order.
    Coloring& coloring = g.coloring;
    coloring.begin(bodies);
    std::size_t coloredJoints = 0;
    while (coloredJoints < g.coloredHost.size() &&
           (all[g.coloredHost[coloredJoints]].id & RUBBLE_PGS_JOINT_ELEMENT)) {
        const ColorElement& x = all[g.coloredHost[coloredJoints++]];
        coloring.add(x.id, x.a, x.b, x.movesA, x.movesB);
    }
    g.coloredPairs.clear();
    for (std::size_t i = coloredJoints; i < g.coloredHost.size(); ++i)
        g.coloredPairs.push_back(all[g.coloredHost[i]]);
    coloring.addBySupport(g.coloredPairs);
    coloring.finish();
    for (std::size_t i = 0; i < g.coloredHost.size(); ++i)
        g.placeHost[g.coloredHost[i]] = inBlocks + coloring.slots()[i];
    // The elements in that order, each pair's rows packed after the last one's, so that a
    // launch reads its rows front to back.
    g.elementsHost.resize(all.size());
    for (std::uint32_t k = 0; k < all.size(); ++k) {
        shared::PgsElement& e = g.elementsHost[g.placeHost[k]];
        e = shared::PgsElement{};
        e.id = all[k].id;
        e.a = all[k].a;
        e.b = all[k].b;
    }
    // pointsHost[i]: the rows before element i (a joint has none). An element of a color has its
    // points' rows in a run from there; a block's are placed by point below.
    g.pointsHost.assign(all.size() + 1, 0);
    std::uint32_t rows = 0;
    for (std::uint32_t i = 0; i < all.size(); ++i) {
        shared::PgsElement& e = g.elementsHost[i];
        if (!(e.id & RUBBLE_PGS_JOINT_ELEMENT)) {
            const cl_uint summary = g.pairRowsHost[e.id];
            const std::uint32_t points = summary & RUBBLE_PGS_POINTS;
            RUBBLE_ASSERT(points <= 4);
            e.rows = summary;
            for (std::uint32_t k = 0; k < points; ++k) e.normal[k] = rows + k;
            rows += points;
        }
        g.pointsHost[i + 1] = rows;
    }
    g.rowCount = rows;
    // A block's rows (normal, friction, impulses) within its range by point: every element's
    // first point, then every second point, ..., the order its passes read them in (solvePgs,
    // warmStartPgs), so that each pass reads them front to back as the CPU's sweep reads its
    // interleaved rows.
    // The block's passes, as many as its elements' most points (one at least: a joint goes with
    // the first), follow the starts: a block of one-point elements (particle contacts) makes one.
    for (std::uint32_t b = 0; b < blocks && inBlocks > 0; ++b) {
        const std::uint32_t from = g.blockStartsHost[b], to = g.blockStartsHost[b + 1];
        std::uint32_t passes = 1;
        for (std::uint32_t i = from; i < to; ++i)
            passes = std::max(passes, g.pointsHost[i + 1] - g.pointsHost[i]);
        std::uint32_t next = g.pointsHost[from];
        for (std::uint32_t k = 0; k < passes; ++k)
            for (std::uint32_t i = from; i < to; ++i)
                if (g.pointsHost[i + 1] - g.pointsHost[i] > k) g.elementsHost[i].normal[k] = next++;
        RUBBLE_ASSERT(next == g.pointsHost[to]);
        g.blockStartsHost.push_back(passes);
    }
    auto pointsIn = [&](std::uint32_t first, std::uint32_t count) {
        return g.pointsHost[first + count] - g.pointsHost[first];
    };
    g.launches.clear();
    if (inBlocks > 0)
        g.launches.push_back({0, inBlocks, RUBBLE_PGS_BLOCKS, pointsIn(0, inBlocks), blocks});
    // One launch per color, but the last colors, once together they hold no more than
    // serialElements (host/gpu/tuning.h), in one launch on one work-item (a launch costs more).
    const std::span<const std::uint32_t> start = coloring.start();
    std::uint32_t tail = coloring.colors();
    const std::uint32_t serial = c.workSizes().serialElements;
    while (tail > 0 && start[coloring.colors()] - start[tail - 1] <= serial) --tail;
    if (coloring.colors() - tail < 2) tail = coloring.colors(); // nothing to merge
    for (std::uint32_t k = 0; k < tail; ++k) {
        const std::uint32_t first = inBlocks + start[k], count = start[k + 1] - start[k];
        g.launches.push_back({first, count, RUBBLE_PGS_PER_ITEM, pointsIn(first, count), 0});
    }
    if (tail < coloring.colors()) {
        const std::uint32_t first = inBlocks + start[tail];
        const std::uint32_t count = start[coloring.colors()] - start[tail];
        g.launches.push_back({first, count, RUBBLE_PGS_SERIAL, pointsIn(first, count), 0});
    }
    if (all.empty()) return {};
    RUBBLE_TRY(reserveGrowing(c, g.normalRows, rows * sizeof(shared::PgsNormalRow)));
    RUBBLE_TRY(reserveGrowing(c, g.frictionRows, rows * sizeof(shared::PgsFrictionRows)));
    RUBBLE_TRY(reserveGrowing(c, g.impulses, rows * sizeof(shared::float4)));
    const std::span<const shared::PgsElement> elements(g.elementsHost);
    RUBBLE_TRY(reserveGrowing(c, g.elements, elements.size_bytes()));
    // Non-blocking: the elements and the build order stay put until the next step's coloring,
    // which waits for this step first. buildPgsRows goes through the pairs' elements in pair
    // order (their slots in the coloring; the joints were added first), which reads the
    // manifolds front to back and nearby bodies together (a color's elements are spread over the
    // pile).
    const std::span<const std::uint32_t> buildOrder =
        std::span<const std::uint32_t>(g.placeHost).subspan(g.jointCount);
    RUBBLE_TRY(reserveGrowing(c, g.buildOrder, std::max<std::size_t>(1, buildOrder.size_bytes())));
    // The blocks' starts go up only when there are blocks (a launch of another mode binds the
    // buffer but reads nothing of it).
    const std::span<const std::uint32_t> blockStarts(g.blockStartsHost);
    RUBBLE_TRY(
        reserveGrowing(c, g.blockStarts, std::max<std::size_t>(4, blockStarts.size_bytes())));
    RUBBLE_TRY(enqueueUpload(c, g.elements, elements, &profile_));
    if (inBlocks > 0) RUBBLE_TRY(enqueueUpload(c, g.blockStarts, blockStarts, &profile_));
    return enqueueUpload(c, g.buildOrder, buildOrder, &profile_);
}

Status Pipeline::buildPgsRows(const StepParams& params) {
    const Context& c = *context_;
    PgsBuffers& g = pgs_;
    // The pairs with rows (the step's elements after the joints).
    const cl_uint count = cl_uint(g.placeHost.size() - g.jointCount);
    if (count == 0) return {};
    RUBBLE_TRY(Dispatch(c, KernelId::BuildPgsRows, &profile_)
                   .arg(count)
                   .arg(g.buildOrder)
                   .arg(g.elements)
                   .arg(sat_.manifolds)
                   .arg(bodies_.poses)
                   .arg(bodies_.velocities)
                   .arg(bodies_.atStart)
                   .arg(bodies_.jacobi)
                   .arg(contacts_.surfaces)
                   .with([&](Dispatch& d) { bindRowSettings(d, params); })
                   .arg(g.normalRows)
                   .arg(g.frictionRows)
                   .arg(g.impulses)
                   .arg(sat_.current.impulses)
                   .run(count, c.workSizes().pairGroup));
    // Per element its record, manifold, both bodies' poses, velocities, JacobiBody and surfaces,
    // last step's run of impulses; per point its rows, impulses and key written.
    const std::uint64_t perElement = sizeof(cl_uint) + sizeof(shared::PgsElement) +
                                     sizeof(shared::ContactManifold) +
                                     2 * (sizeof(shared::BodyPose) + sizeof(shared::BodyVelocity) +
                                          sizeof(shared::JacobiBody) + sizeof(shared::float4)) +
                                     4 * sizeof(shared::PgsImpulse);
    const std::uint64_t perPoint = sizeof(shared::PgsNormalRow) + sizeof(shared::PgsFrictionRows) +
                                   sizeof(shared::float4) + sizeof(shared::PgsImpulse);
    profile_.setLastBytes(count * perElement + g.rowCount * perPoint);
    return {};
}

Status Pipeline::solvePgs(const StepParams& params) {
    const Context& c = *context_;
    PgsBuffers& g = pgs_;
    const SolverOptions& o = params.solver;
    const std::size_t group = c.workSizes().pairGroup;
    const cl_float relaxation = o.relaxation;
    const std::uint64_t rowBytes = sizeof(shared::PgsNormalRow) + sizeof(shared::PgsFrictionRows);
    RUBBLE_TRY(copyVelocities(bodies_.before));
    if (o.warmStart) {
        for (const PgsLaunch& l : g.launches) {
            RUBBLE_TRY(sweepLaunch(c, KernelId::WarmStartPgs, l, g, &profile_)
                           .arg(g.normalRows)
                           .arg(g.frictionRows)
                           .arg(g.impulses)
                           .arg(g.joints)
                           .arg(g.jointRows)
                           .arg(bodies_.jacobi)
                           .arg(bodies_.velocities)
                           .run(l.items(group), group));
            profile_.setLastBytes(sweepBytes(l.count, l.points, rowBytes));
        }
    }
    // The split position pass, when a row pushes or may bounce (the coloring read the status
    // after the summaries), on push velocities that start at zero: its sweep k runs in the
    // launches of velocity sweep k, unless a row may bounce, whose target the velocity sweeps
    // decide (markBounces): then it runs after them.
    g.bounces = o.iterations > 0 && !g.launches.empty() && statusHost_[RUBBLE_STATUS_BOUNCES] != 0;
    g.pushes = o.iterations > 0 && !g.launches.empty() &&
               (statusHost_[RUBBLE_STATUS_PUSHED] != 0 || g.bounces);
    const bool pushes = g.pushes, fused = g.fusedPushes();
    const std::size_t sweeps = std::size_t(std::max(o.iterations, 0));
    if (pushes) {
        const std::size_t n = bodies_.count;
        RUBBLE_TRY(fill(c, g.push, 0u, n * sizeof(shared::BodyVelocity), &profile_));
        RUBBLE_TRY(reserveGrowing(c, g.sweepResidual, sweeps * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, g.sweepResidual, 0u, sweeps * sizeof(cl_uint), &profile_));
    }
    for (int it = 0; it < o.iterations; ++it) {
        const cl_uint last = it + 1 == o.iterations ? 1u : 0u;
        const cl_uint pushSweep = fused ? cl_uint(it) : RUBBLE_PGS_NO_PUSH;
        for (const PgsLaunch& l : g.launches) {
            RUBBLE_TRY(sweepLaunch(c, KernelId::SolvePgs, l, g, &profile_)
                           .arg(g.normalRows)
                           .arg(g.frictionRows)
                           .arg(g.impulses)
                           .arg(g.joints)
                           .arg(g.jointRows)
                           .arg(bodies_.jacobi)
                           .arg(bodies_.velocities)
                           .arg(relaxation)
                           .arg(last)
                           .arg(cl_uint(it))
                           .arg(sat_.current.impulses)
                           .arg(status_)
                           .arg(pushSweep)
                           .arg(g.pushed)
                           .arg(g.push)
                           .arg(g.sweepResidual)
                           .run(l.items(group), group));
            // The push sweep reads the normal rows again (from cache), its velocities and
            // impulses, and both bodies' push marks.
            const std::uint64_t push =
                fused ? l.count * (4 * sizeof(shared::BodyVelocity) + 8) + l.points * 32 : 0;
            profile_.setLastBytes(sweepBytes(l.count, l.points, rowBytes) + push +
                                  (last ? l.points * sizeof(shared::PgsImpulse) : 0));
        }
    }
    if (pushes && !fused) {
        // The rows that bounce aim the pass at their lift, then the pass on its own.
        const cl_uint count = cl_uint(g.elementsHost.size());
        RUBBLE_TRY(Dispatch(c, KernelId::MarkBounces, &profile_)
                       .arg(count)
                       .arg(g.elements)
                       .arg(g.normalRows)
                       .arg(g.impulses)
                       .arg(g.pushed)
                       .arg(status_)
                       .run(count, group));
        profile_.setLastBytes(count * sizeof(shared::PgsElement) +
                              g.rowCount * (sizeof(shared::PgsNormalRow) + sizeof(shared::float4)));
        for (cl_uint sweep = 0; sweep < sweeps; ++sweep) {
            for (const PgsLaunch& l : g.launches) {
                RUBBLE_TRY(sweepLaunch(c, KernelId::PushPgs, l, g, &profile_)
                               .arg(g.normalRows)
                               .arg(g.impulses)
                               .arg(g.pushed)
                               .arg(g.push)
                               .arg(relaxation)
                               .arg(sweep)
                               .arg(g.sweepResidual)
                               .run(l.items(group), group));
                profile_.setLastBytes(
                    l.count * (sizeof(shared::PgsElement) + 4 * sizeof(shared::BodyVelocity) + 8) +
                    l.points * (sizeof(shared::PgsNormalRow) + 2 * sizeof(shared::float4)));
            }
        }
    }
    // The layer pass, when the summaries found moving bodies that far apart in mass.
    if (!g.launches.empty() && statusHost_[RUBBLE_STATUS_LAYERS] != 0) {
        const std::size_t n = bodies_.count;
        const std::size_t rows = std::max<std::size_t>(1, g.rowCount);
        RUBBLE_TRY(reserveGrowing(c, g.layer, n * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, g.loaded, n * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, g.layerHistogram, (n + 1) * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, g.layerRows, rows * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, g.layerSorted, rows * sizeof(cl_uint)));
        const cl_uint count = cl_uint(g.elementsHost.size()), bodyCount = bodies_.count;
        const cl_uint joints = g.jointCount, pushPass = pushes ? 1u : 0u;
        RUBBLE_TRY(Dispatch(c, KernelId::LayerPgs, &profile_)
                       .arg(count)
                       .arg(g.elements)
                       .arg(g.normalRows)
                       .arg(g.impulses)
                       .arg(bodies_.jacobi)
                       .arg(bodyCount)
                       .arg(g.joints)
                       .arg(joints)
                       .arg(bodies_.velocities)
                       .arg(pushPass)
                       .arg(g.pushed)
                       .arg(g.push)
                       .arg(status_)
                       .arg(g.layer)
                       .arg(g.loaded)
                       .arg(g.layerRows)
                       .arg(g.layerSorted)
                       .arg(g.layerHistogram)
                       .run(1, 1));
        // At least: every element and row read once, each body's layer and marks.
        profile_.setLastBytes(count * sizeof(shared::PgsElement) +
                              g.rowCount * sizeof(shared::PgsNormalRow) +
                              n * (sizeof(shared::JacobiBody) + 2 * sizeof(cl_uint)));
    }
    if (g.bounces) {
        RUBBLE_TRY(reserveGrowing(c, g.solved, bodies_.count * sizeof(shared::BodyVelocity)));
        RUBBLE_TRY(copyVelocities(g.solved));
    }
    return absorbVelocityChange();
}

Status Pipeline::bouncePgs(const StepParams& params) {
    PgsBuffers& g = pgs_;
    if (!g.bounces) return {};
    const Context& c = *context_;
    const std::size_t group = c.workSizes().pairGroup;
    const std::size_t sweeps = std::size_t(std::max(params.solver.iterations, 0));
    RUBBLE_TRY(reserveGrowing(c, g.bounce, std::max<std::size_t>(1, g.rowCount) * sizeof(float)));
    RUBBLE_TRY(reserveGrowing(c, g.bounceResidual, sweeps * sizeof(cl_uint)));
    RUBBLE_TRY(fill(c, g.bounceResidual, 0u, sweeps * sizeof(cl_uint), &profile_));
    // Per launch: each element's record and bodies' velocities read and written, each point's
    // normal row and impulses read, its bounce impulse read and written.
    auto bytes = [](const PgsLaunch& l) -> std::uint64_t {
        return l.count * (sizeof(shared::PgsElement) + 4 * sizeof(shared::BodyVelocity)) +
               l.points * (sizeof(shared::PgsNormalRow) + sizeof(shared::float4) + 8);
    };
    for (cl_uint sweep = 0; sweep < sweeps; ++sweep) {
        for (const PgsLaunch& l : g.launches) {
            RUBBLE_TRY(sweepLaunch(c, KernelId::BouncePgs, l, g, &profile_)
                           .arg(g.normalRows)
                           .arg(g.impulses)
                           .arg(g.bounce)
                           .arg(g.solved)
                           .arg(sweep)
                           .arg(g.bounceResidual)
                           .run(l.items(group), group));
            profile_.setLastBytes(bytes(l));
        }
    }
    for (const PgsLaunch& l : g.launches) {
        RUBBLE_TRY(sweepLaunch(c, KernelId::BounceMomenta, l, g, &profile_)
                       .arg(g.normalRows)
                       .arg(g.impulses)
                       .arg(g.bounce)
                       .arg(bodies_.momenta)
                       .arg(bodies_.masses)
                       .arg(bodies_.poses)
                       .arg(bodies_.velocities)
                       .run(l.items(group), group));
        profile_.setLastBytes(bytes(l) + l.count * 2 *
                                             (2 * sizeof(shared::BodyMomentum) +
                                              sizeof(shared::BodyMass) + sizeof(shared::BodyPose)));
    }
    return {};
}

Status Pipeline::applyPushes(float dt) {
    // The kernel moves nothing unless a row pushed (the status block says, after markBounces).
    if (!pgs_.pushes) return {};
    const cl_uint count = bodies_.count;
    const cl_float step = dt;
    return Dispatch(*context_, KernelId::ApplyPushes, &profile_)
        .arg(count)
        .arg(status_)
        .arg(bodies_.jacobi)
        .arg(pgs_.push)
        .arg(bodies_.momenta)
        .arg(bodies_.masses)
        .arg(bodies_.poses)
        .arg(bodies_.velocities)
        .arg(step)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status Pipeline::projectJoints() {
    PgsBuffers& g = pgs_;
    if (g.jointCount == 0) return {};
    const Context& c = *context_;
    RUBBLE_TRY(
        fill(c, g.jointMoved, 0u, RUBBLE_JOINT_POSITION_ITERATIONS * sizeof(cl_uint), &profile_));
    if (g.directGroupCount > 0) {
        const cl_uint groups = g.directGroupCount;
        const cl_int iterations = RUBBLE_JOINT_POSITION_ITERATIONS;
        RUBBLE_TRY(Dispatch(c, KernelId::ProjectJointGroups, &profile_)
                       .arg(groups)
                       .arg(g.directGroups)
                       .arg(g.groupMembers)
                       .arg(g.joints)
                       .arg(bodies_.masses)
                       .arg(bodies_.flags)
                       .arg(bodies_.poses)
                       .arg(g.positionRows)
                       .arg(g.positionMatrix)
                       .arg(g.positionSolution)
                       .arg(g.deltaPosition)
                       .arg(g.deltaRotation)
                       .arg(iterations)
                       .run(groups, 1));
    }
    const Coloring& coloring = g.jointColoring;
    const std::span<const std::uint32_t> start = coloring.start();
    for (cl_uint sweep = 0; sweep < RUBBLE_JOINT_POSITION_ITERATIONS && coloring.colors() > 0;
         ++sweep) {
        for (std::uint32_t k = 0; k < coloring.colors(); ++k) {
            const cl_uint first = start[k], count = start[k + 1] - start[k];
            RUBBLE_TRY(Dispatch(c, KernelId::ProjectJoints, &profile_)
                           .arg(first)
                           .arg(count)
                           .arg(g.jointOrder)
                           .arg(g.joints)
                           .arg(bodies_.masses)
                           .arg(bodies_.flags)
                           .arg(bodies_.poses)
                           .arg(sweep)
                           .arg(g.jointMoved)
                           .run(count, RUBBLE_GROUP_BODIES));
            // The joint, both bodies' masses, flags and poses (read and written).
            profile_.setLastBytes(count * (sizeof(shared::PgsJoint) + 2 * sizeof(shared::BodyMass) +
                                           2 * sizeof(cl_uint) + 4 * sizeof(shared::BodyPose)));
        }
    }
    const cl_uint bodies = g.jointBodyCount;
    return Dispatch(c, KernelId::JointVelocities, &profile_)
        .arg(bodies)
        .arg(g.jointBodies)
        .arg(bodies_.masses)
        .arg(bodies_.flags)
        .arg(bodies_.poses)
        .arg(bodies_.momenta)
        .arg(bodies_.velocities)
        .run(bodies, RUBBLE_GROUP_BODIES);
}

Result<std::vector<shared::PgsNormalRow>> Pipeline::downloadPgsNormalRows() {
    return download<shared::PgsNormalRow>(*context_, pgs_.normalRows, pgs_.rowCount);
}

Result<std::vector<shared::PgsFrictionRows>> Pipeline::downloadPgsFrictionRows() {
    return download<shared::PgsFrictionRows>(*context_, pgs_.frictionRows, pgs_.rowCount);
}

} // namespace rubble::gpu
