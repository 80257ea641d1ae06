// host/gpu/pgs_plan.cpp: the host's plan of a PGS step on the device: the pairs' summaries
// read back, the step's elements split into blocks (a CPU device) and colors, their records and
// rows' places, and the launches of each sweep. Run each step between the summaries and the
// rows; the device waits for it.
#include <algorithm>

#include "host/core/assert.h"
#include "host/gpu/pgs.h"

namespace rubble::gpu {
Status PgsSolve::readSummaries(StageQueue& q, const PairStore& pairs) {
    if (summariesRead_) return {};
    const Context& c = q.c();
    // The status block was read after the summaries (readStatus waited for them).
    const std::uint32_t count = std::min(q.lastStatus().pairs, pairs.current.capacity);
    summariesHost_.resize(count);
    pairsHost_.resize(count);
    // Both reads queued, then one wait.
    RUBBLE_TRY(enqueueDownload(c, pairs.summaries, std::span(summariesHost_), &q.profile()));
    RUBBLE_TRY(download(c, pairs.current.pairs, std::span(pairsHost_), &q.profile()));
    summariesRead_ = true;
    return {};
}

void PgsSolve::touching(std::vector<BodyPair>& out) const {
    out.clear();
    for (std::size_t p = 0; p < summariesHost_.size(); ++p)
        if (summariesHost_[p] & RUBBLE_PGS_POINTS)
            out.push_back({pairsHost_[p].a, pairsHost_[p].b});
}

Status PgsSolve::plan(StageQueue& q, const PairStore& pairs, const DeviceJoints& joints,
                      const DeviceBodies& bodyBuffers, const DeviceStatus& st) {
    if (devicePlan_) return planOnDevice(q, pairs, joints, bodyBuffers, st);
    const Context& c = q.c();
    const std::uint32_t bodyCount = bodyBuffers.count;
    // The device idles from here until the coloring's upload.
    RUBBLE_TRY(readSummaries(q, pairs));
    const auto pairCount = std::uint32_t(pairsHost_.size());
    // The elements: the joints first (the CPU's sweep solves them before the contacts), then the
    // pairs with rows in pair order.
    stepElements_.clear();
    for (std::uint32_t j = 0; j < joints.count; ++j)
        stepElements_.push_back({RUBBLE_PGS_JOINT_ELEMENT | j, joints.host[j].a, joints.host[j].b,
                                 joints.dynamicA[j] != 0, joints.dynamicB[j] != 0});
    for (std::uint32_t p = 0; p < pairCount; ++p) {
        const cl_uint summary = summariesHost_[p];
        if ((summary & RUBBLE_PGS_POINTS) == 0) continue;
        stepElements_.push_back({p, pairsHost_[p].a, pairsHost_[p].b,
                                 (summary & RUBBLE_PGS_MOVES_A) != 0,
                                 (summary & RUBBLE_PGS_MOVES_B) != 0});
    }
    const std::span<const ColorElement> all(stepElements_);
    // Blocks (a CPU device): the bodies cut into ranges of indices, an element whose moving
    // bodies are all in one range goes to that range's block, in the order above; a block runs
    // in order on one work-item, as the CPU's sweep does (docs/opencl.md, "Blocks"). The rest,
    // between blocks, and every element on a GPU, are colored.
    const std::uint32_t blocks = blocks_, bodies = bodyCount;
    jointCount_ = joints.count;
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
    blockOfHost_.resize(all.size());
    blockStartsHost_.assign(std::size_t(blocks) + 1, 0);
    coloredHost_.clear();
    for (std::uint32_t k = 0; k < all.size(); ++k) {
        const std::uint32_t b = blockOfHost_[k] = blockOf(all[k]);
        if (b == kColored)
            coloredHost_.push_back(k);
        else
            ++blockStartsHost_[b + 1];
    }
    for (std::uint32_t b = 0; b < blocks; ++b) blockStartsHost_[b + 1] += blockStartsHost_[b];
    const std::uint32_t inBlocks = blockStartsHost_[blocks];
    // Where each element goes: its block's next place, or (below) its place among the colors
    // after the blocks.
    placeHost_.resize(all.size());
    nextHost_.assign(blockStartsHost_.begin(), blockStartsHost_.end());
    for (std::uint32_t k = 0; k < all.size(); ++k)
        if (blockOfHost_[k] != kColored) placeHost_[k] = nextHost_[blockOfHost_[k]]++;
    // The colored elements: greedy, joints one by one, the pairs from the bottom up
    // (Coloring::addBySupport), each color in pair order.
    Coloring& coloring = coloring_;
    coloring.begin(bodies);
    std::size_t coloredJoints = 0;
    while (coloredJoints < coloredHost_.size() &&
           (all[coloredHost_[coloredJoints]].id & RUBBLE_PGS_JOINT_ELEMENT)) {
        const ColorElement& x = all[coloredHost_[coloredJoints++]];
        coloring.add(x.id, x.a, x.b, x.movesA, x.movesB);
    }
    coloredPairs_.clear();
    for (std::size_t i = coloredJoints; i < coloredHost_.size(); ++i)
        coloredPairs_.push_back(all[coloredHost_[i]]);
    coloring.addBySupport(coloredPairs_);
    coloring.finish();
    for (std::size_t i = 0; i < coloredHost_.size(); ++i)
        placeHost_[coloredHost_[i]] = inBlocks + coloring.slots()[i];
    // The elements in that order, each pair's rows packed after the last one's, so that a
    // launch reads its rows front to back.
    elementsHost_.resize(all.size());
    for (std::uint32_t k = 0; k < all.size(); ++k) {
        shared::PgsElement& e = elementsHost_[placeHost_[k]];
        e = shared::PgsElement{};
        e.id = all[k].id;
        e.a = all[k].a;
        e.b = all[k].b;
    }
    // pointsHost[i]: the rows before element i (a joint has none). An element of a color has its
    // points' rows in a run from there; a block's are placed by point below.
    pointsHost_.assign(all.size() + 1, 0);
    std::uint32_t rows = 0;
    for (std::uint32_t i = 0; i < all.size(); ++i) {
        shared::PgsElement& e = elementsHost_[i];
        if (!(e.id & RUBBLE_PGS_JOINT_ELEMENT)) {
            const cl_uint summary = summariesHost_[e.id];
            const std::uint32_t points = summary & RUBBLE_PGS_POINTS;
            RUBBLE_ASSERT(points <= 4);
            e.rows = summary;
            for (std::uint32_t k = 0; k < points; ++k) e.normal[k] = rows + k;
            rows += points;
        }
        pointsHost_[i + 1] = rows;
    }
    rowCount_ = rowRoom_ = rows;
    elementRoom_ = std::uint32_t(all.size());
    buildCount_ = std::uint32_t(all.size()) - joints.count;
    // A block's rows (normal, friction, impulses) within its range by point: every element's
    // first point, then every second point, ..., the order its passes read them in (solvePgs,
    // warmStartPgs), so that each pass reads them front to back as the CPU's sweep reads its
    // interleaved rows.
    // The block's passes, as many as its elements' most points (one at least: a joint goes with
    // the first), follow the starts: a block of one-point elements (particle contacts) makes one.
    for (std::uint32_t b = 0; b < blocks && inBlocks > 0; ++b) {
        const std::uint32_t from = blockStartsHost_[b], to = blockStartsHost_[b + 1];
        std::uint32_t passes = 1;
        for (std::uint32_t i = from; i < to; ++i)
            passes = std::max(passes, pointsHost_[i + 1] - pointsHost_[i]);
        std::uint32_t next = pointsHost_[from];
        for (std::uint32_t k = 0; k < passes; ++k)
            for (std::uint32_t i = from; i < to; ++i)
                if (pointsHost_[i + 1] - pointsHost_[i] > k) elementsHost_[i].normal[k] = next++;
        RUBBLE_ASSERT(next == pointsHost_[to]);
        blockStartsHost_.push_back(passes);
    }
    auto pointsIn = [&](std::uint32_t first, std::uint32_t count) {
        return pointsHost_[first + count] - pointsHost_[first];
    };
    launches_.clear();
    if (inBlocks > 0)
        launches_.push_back({0, inBlocks, RUBBLE_PGS_BLOCKS, pointsIn(0, inBlocks), blocks});
    // One launch per color, but the last colors, once together they hold no more than
    // serialElements (host/gpu/tuning.h), in one launch on one work-item (a launch costs more).
    const std::span<const std::uint32_t> start = coloring.start();
    std::uint32_t tail = coloring.colors();
    const std::uint32_t serial = q.c().workSizes().serialElements;
    while (tail > 0 && start[coloring.colors()] - start[tail - 1] <= serial) --tail;
    if (coloring.colors() - tail < 2) tail = coloring.colors(); // nothing to merge
    for (std::uint32_t k = 0; k < tail; ++k) {
        const std::uint32_t first = inBlocks + start[k], count = start[k + 1] - start[k];
        launches_.push_back({first, count, RUBBLE_PGS_PER_ITEM, pointsIn(first, count), 0});
    }
    if (tail < coloring.colors()) {
        const std::uint32_t first = inBlocks + start[tail];
        const std::uint32_t count = start[coloring.colors()] - start[tail];
        launches_.push_back({first, count, RUBBLE_PGS_SERIAL, pointsIn(first, count), 0});
    }
    if (all.empty()) return {};
    RUBBLE_TRY(reserveGrowing(c, normalRows_, rows * sizeof(shared::PgsNormalRow)));
    RUBBLE_TRY(reserveGrowing(c, frictionRows_, rows * sizeof(shared::PgsFrictionRows)));
    RUBBLE_TRY(reserveGrowing(c, impulses_, rows * sizeof(shared::float4)));
    const std::span<const shared::PgsElement> elements(elementsHost_);
    RUBBLE_TRY(reserveGrowing(c, elements_, elements.size_bytes()));
    // Non-blocking: the elements and the build order stay put until the next step's coloring,
    // which waits for this step first. buildPgsRows goes through the pairs' elements in pair
    // order (their slots in the coloring; the joints were added first), which reads the
    // manifolds front to back and nearby bodies together (a color's elements are spread over the
    // pile).
    const std::span<const std::uint32_t> buildOrder =
        std::span<const std::uint32_t>(placeHost_).subspan(joints.count);
    RUBBLE_TRY(reserveGrowing(c, buildOrder_, std::max<std::size_t>(1, buildOrder.size_bytes())));
    // The blocks' starts go up only when there are blocks (a launch of another mode binds the
    // buffer but reads nothing of it).
    const std::span<const std::uint32_t> blockStarts(blockStartsHost_);
    RUBBLE_TRY(reserveGrowing(c, blockStarts_, std::max<std::size_t>(4, blockStarts.size_bytes())));
    RUBBLE_TRY(enqueueUpload(c, elements_, elements, &q.profile()));
    if (inBlocks > 0) RUBBLE_TRY(enqueueUpload(c, blockStarts_, blockStarts, &q.profile()));
    return enqueueUpload(c, buildOrder_, buildOrder, &q.profile());
}

} // namespace rubble::gpu
