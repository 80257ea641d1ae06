// host/gpu/pgs_device_plan.cpp: the device's plan of the colored solve (no blocks): the
// elements colored, sorted by color and given their rows' places by kernels/coloring.cl, between
// the summaries and the rows, with nothing read back to wait for. The host's plan is
// host/gpu/pgs_plan.cpp; the launches' count is the same every step (docs/opencl.md, "Coloring
// on the device").
#include <algorithm>

#include "host/gpu/pgs.h"
#include "rubble/shared/pgs_coloring.h"

namespace rubble::gpu {

Status PgsSolve::createDevicePlan(StageQueue& q, std::uint32_t bodies) {
    const Context& c = q.c();
    const std::size_t n = std::max<std::uint32_t>(bodies, 1);
    RUBBLE_TRY(bodyColors_.reserve(c.context(), n * sizeof(cl_uint)));
    // Two steps' levels, none known yet.
    for (Buffer& levels : levels_) {
        RUBBLE_TRY(levels.reserve(c.context(), n * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, levels, RUBBLE_PGS_NO_LEVEL, n * sizeof(cl_uint)));
    }
    // Every claim starts clear; each round leaves them clear (takeColors).
    RUBBLE_TRY(claims_.reserve(c.context(), n * RUBBLE_PGS_COLORS * sizeof(cl_uint)));
    RUBBLE_TRY(fill(c, claims_, RUBBLE_PGS_NO_CLAIM, n * RUBBLE_PGS_COLORS * sizeof(cl_uint)));
    const std::size_t sets = RUBBLE_PGS_COLORS + 1;
    RUBBLE_TRY(
        chunkCounts_.reserve(c.context(), 2 * sets * RUBBLE_PGS_COLOR_CHUNKS * sizeof(cl_uint)));
    RUBBLE_TRY(colorStarts_.reserve(c.context(), RUBBLE_PGS_COLOR_STARTS_WORDS * sizeof(cl_uint)));
    colorStartsHost_.assign(RUBBLE_PGS_COLOR_STARTS_WORDS, 0);
    colorStartsKnown_ = false;
    return {};
}

Status PgsSolve::planOnDevice(StageQueue& q, const PairStore& pairs, const DeviceJoints& joints,
                              const DeviceBodies& b, const DeviceStatus& st) {
    const Context& c = q.c();
    const std::size_t group = c.workSizes().pairGroup;
    const cl_uint jointCount = joints.count, capacity = pairs.current.capacity;
    const cl_uint bodyCount = b.count;
    jointCount_ = jointCount;
    // Room from what the host knows without waiting: every joint and every pair the pair
    // buffers hold, each pair at most four points (a ContactManifold holds four).
    elementRoom_ = jointCount + capacity;
    buildCount_ = capacity;
    rowRoom_ = 4 * capacity;
    // The launches: one per color and one for the overflow set, each as wide as last step's
    // color (read without waiting at the end of last step's plan) and a quarter more, at least a
    // group; the launches stride, so their size changes the speed, never the result.
    const std::span<const cl_uint> last(colorStartsHost_);
    launches_.clear();
    for (cl_uint k = 0; k <= RUBBLE_PGS_COLORS; ++k) {
        const std::uint32_t count = colorStartsKnown_ ? last[k + 1] - last[k] : 0;
        const std::uint32_t points = colorStartsKnown_ ? last[RUBBLE_PGS_COLOR_ROW_STARTS + k + 1] -
                                                             last[RUBBLE_PGS_COLOR_ROW_STARTS + k]
                                                       : 0;
        const bool overflow = k == RUBBLE_PGS_OVERFLOW_SET;
        launches_.push_back({k, count, overflow ? RUBBLE_PGS_OVERFLOW : RUBBLE_PGS_COLOR, points, 0,
                             std::uint32_t(roundUp(count + count / 4, group))});
    }
    rowCount_ = colorStartsKnown_ ? last[RUBBLE_PGS_COLOR_STARTS_WORDS - 1] : 0;
    // These rooms change only when the pair buffers grow, which they do by their own margin:
    // sized exactly (not half as much again, as per-step counts are), since a four-point bound
    // on every pair the broad phase may find is already far more than a pile takes.
    const std::size_t elementBytes = std::size_t(elementRoom_) * sizeof(shared::PgsElement);
    const std::size_t rowRoom = std::max<std::size_t>(1, rowRoom_);
    RUBBLE_TRY(normalRows_.reserve(c.context(), rowRoom * sizeof(shared::PgsNormalRow)));
    RUBBLE_TRY(frictionRows_.reserve(c.context(), rowRoom * sizeof(shared::PgsFrictionRows)));
    RUBBLE_TRY(impulses_.reserve(c.context(), rowRoom * sizeof(shared::float4)));
    RUBBLE_TRY(elements_.reserve(c.context(), std::max<std::size_t>(1, elementBytes)));
    RUBBLE_TRY(colorOf_.reserve(c.context(), std::max<cl_uint>(1, elementRoom_) * sizeof(cl_uint)));
    RUBBLE_TRY(buildOrder_.reserve(c.context(), std::max<cl_uint>(1, capacity) * sizeof(cl_uint)));
    // The pairs past this round's count keep no element; markBounces and the layer pass go
    // through every record there is room for, those past the step's elements zero (no points).
    RUBBLE_TRY(
        fill(c, buildOrder_, RUBBLE_PGS_NO_ELEMENT, capacity * sizeof(cl_uint), &q.profile()));
    if (st.bounces || st.layers) RUBBLE_TRY(fill(c, elements_, 0u, elementBytes, &q.profile()));
    const std::size_t items = q.strideItems(std::max(elementRoom_, bodyCount), group);
    // This step's levels in one of levels_, last step's in the other.
    levelHalf_ ^= 1u;
    const Buffer& level = levels_[levelHalf_];
    const Buffer& lastLevel = levels_[levelHalf_ ^ 1u];
    RUBBLE_TRY(Dispatch(c, KernelId::BeginColoring, &q.profile())
                   .arg(jointCount)
                   .arg(capacity)
                   .arg(pairs.current.count)
                   .arg(pairs.summaries)
                   .arg(colorOf_)
                   .arg(bodyCount)
                   .arg(b.jacobi)
                   .arg(bodyColors_)
                   .arg(level)
                   .run(items, group));
    RUBBLE_TRY(Dispatch(c, KernelId::RelaxLevels, &q.profile())
                   .arg(jointCount)
                   .arg(capacity)
                   .arg(pairs.current.count)
                   .arg(pairs.current.pairs)
                   .arg(pairs.summaries)
                   .arg(lastLevel)
                   .arg(level)
                   .run(q.strideItems(capacity, group), group));
    // The rounds: each chooses, then takes.
    auto round = [&](KernelId id) {
        return Dispatch(c, id, &q.profile())
            .arg(jointCount)
            .arg(capacity)
            .arg(pairs.current.count)
            .arg(pairs.current.pairs)
            .arg(pairs.summaries)
            .arg(joints.joints)
            .arg(b.jacobi)
            .arg(colorOf_)
            .arg(level)
            .arg(bodyColors_)
            .arg(claims_)
            .run(q.strideItems(elementRoom_, group), group);
    };
    for (std::uint32_t r = 0; r < RUBBLE_PGS_COLOR_ROUNDS; ++r) {
        RUBBLE_TRY(round(KernelId::ChooseColors));
        RUBBLE_TRY(round(KernelId::TakeColors));
    }
    // The counting sort by color, chunk by chunk, and the color starts.
    constexpr std::size_t kChunkGroup = 64;
    RUBBLE_TRY(Dispatch(c, KernelId::CountColors, &q.profile())
                   .arg(jointCount)
                   .arg(capacity)
                   .arg(pairs.current.count)
                   .arg(pairs.summaries)
                   .arg(colorOf_)
                   .arg(chunkCounts_)
                   .run(RUBBLE_PGS_COLOR_CHUNKS, kChunkGroup));
    RUBBLE_TRY(Dispatch(c, KernelId::ScanColors, &q.profile())
                   .arg(chunkCounts_)
                   .arg(colorStarts_)
                   .run(1, 1));
    RUBBLE_TRY(Dispatch(c, KernelId::PlaceColors, &q.profile())
                   .arg(jointCount)
                   .arg(capacity)
                   .arg(pairs.current.count)
                   .arg(pairs.current.pairs)
                   .arg(pairs.summaries)
                   .arg(joints.joints)
                   .arg(colorOf_)
                   .arg(chunkCounts_)
                   .arg(elements_)
                   .arg(buildOrder_)
                   .run(RUBBLE_PGS_COLOR_CHUNKS, kChunkGroup));
    // Non-blocking: the next step's launches take their sizes from it, after this step is met.
    RUBBLE_TRY(enqueueDownload(c, colorStarts_, std::span(colorStartsHost_), &q.profile()));
    colorStartsKnown_ = true;
    return {};
}

Result<std::vector<cl_uint>> PgsSolve::downloadColorStarts(StageQueue& q) const {
    return download<cl_uint>(q.c(), colorStarts_, RUBBLE_PGS_COLOR_STARTS_WORDS);
}

Result<std::vector<cl_uint>> PgsSolve::downloadColorOf(StageQueue& q,
                                                       std::uint32_t elements) const {
    return download<cl_uint>(q.c(), colorOf_, elements);
}

Result<std::vector<shared::PgsElement>> PgsSolve::downloadElements(StageQueue& q,
                                                                   std::uint32_t count) const {
    return download<shared::PgsElement>(q.c(), elements_, count);
}

} // namespace rubble::gpu
