// host/gpu/broad_phase.cpp: dispatch of the SAT broad phase on the device (kernels/
// broad_phase.cl): computeAabbs, then findPairs by sweep and prune in columns with the pairs
// sorted by (a, b). The CPU twin is SatCollision::broadPhase and findPairs (host/collision/).
#include "host/gpu/broad_phase.h"

#include <algorithm>

#include "host/core/assert.h"

namespace rubble::gpu {
namespace {

// The bits of a grid of at least 4096 columns and one per four bodies: columns of two mean box
// widths over one layer of bodies hold about that many, and a pile holds more. Columns widened
// to fit cost longer sweeps, not more entries; fewer key bits cost fewer passes of the sort.
std::uint32_t gridBitsFor(std::uint32_t bodies) {
    const std::uint64_t cells = std::max<std::uint64_t>(4096, std::uint64_t(bodies) / 4);
    std::uint32_t bits = 1;
    while ((std::uint64_t(1) << bits) < cells) ++bits;
    return bits;
}

// The sweep keys' bits below a column key of gridBits: at least 12 (steps of 1/4096 of the
// boxes' range), filling the sort's last digit, within 32 bits in all.
std::uint32_t sweepBitsFor(std::uint32_t gridBits) {
    const std::uint32_t digit = RUBBLE_SORT_DIGIT_BITS;
    const std::uint32_t total =
        std::min<std::uint32_t>(32, (gridBits + 12 + digit - 1) / digit * digit);
    return total - gridBits;
}

} // namespace

Status SatBroadPhase::create(StageQueue& q, BodiesView bodies, std::span<const Shape> shapes,
                             std::span<const BodyPair> joinedPairs) {
    const Context& c = q.c();
    const auto n = std::uint32_t(bodies.count());
    std::vector<cl_uint> planes;
    for (std::uint32_t i = 0; i < n; ++i) {
        RUBBLE_ASSERT(bodies.shapeOf[i] < shapes.size());
        if (shapes[bodies.shapeOf[i]].type == ShapeType::Plane) planes.push_back(i);
    }
    planeCount_ = std::uint32_t(planes.size());
    RUBBLE_TRY(upload(c, planes_, planes));
    std::vector<shared::BodyPairRecord> joined;
    for (const BodyPair& p : joinedPairs)
        joined.push_back({std::min(p.a, p.b), std::max(p.a, p.b)});
    std::sort(joined.begin(), joined.end(),
              [](const auto& x, const auto& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); });
    joinedCount_ = std::uint32_t(joined.size());
    RUBBLE_TRY(upload(c, joined_, joined));

    // Per body.
    RUBBLE_TRY(boxes_.reserve(c.context(), n * sizeof(shared::BodyBox)));
    RUBBLE_TRY(spin_.reserve(c.context(), n * sizeof(cl_float)));
    RUBBLE_TRY(broadFlags_.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(bodyCount_.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(bodyStart_.reserve(c.context(), (n + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(cursor_.reserve(c.context(), (n + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(large_.reserve(c.context(), n * sizeof(cl_uint)));
    // The columns: at most 4 entries (2 x 2 columns) per body.
    gridBits_ = gridBitsFor(n);
    sweepBits_ = sweepBitsFor(gridBits_);
    RUBBLE_TRY(
        partials_.reserve(c.context(), c.workSizes().sortItems * sizeof(shared::GridPartial)));
    RUBBLE_TRY(grid_.reserve(c.context(), sizeof(shared::GridParams)));
    for (Buffer* b : {&keys_, &values_, &keysAlt_, &valuesAlt_})
        RUBBLE_TRY(b->reserve(c.context(), 4 * std::size_t(n) * sizeof(cl_uint)));
    return cellBoxes_.reserve(c.context(), 4 * std::size_t(n) * sizeof(shared::BodyBox));
}

Status SatBroadPhase::run(StageQueue& q, const DeviceBodies& b, const DeviceShapes& shapes,
                          PairStore& pairs, RadixSort& sort, float dt) {
    RUBBLE_TRY(computeAabbs(q, b, shapes, dt));
    return findPairs(q, b, pairs, sort);
}

Status SatBroadPhase::computeAabbs(StageQueue& q, const DeviceBodies& b, const DeviceShapes& shapes,
                                   float dt) {
    const cl_uint count = b.count;
    const cl_float step = dt;
    return Dispatch(q.c(), KernelId::ComputeAabbs, &q.profile())
        .arg(count)
        .arg(step)
        .arg(shapes.shapes)
        .arg(shapes.shapeOf)
        .arg(b.poses)
        .arg(b.velocities)
        .arg(b.flags)
        .arg(boxes_)
        .arg(spin_)
        .arg(broadFlags_)
        .run(count, q.c().workSizes().broadGroup);
}

Status SatBroadPhase::findPairs(StageQueue& q, const DeviceBodies& b, PairStore& pairs,
                                RadixSort& sort) {
    const Context& c = q.c();
    Profile* profile = &q.profile();
    const WorkSizes& sizes = c.workSizes();
    const cl_uint count = b.count;
    const cl_uint entries = 4 * count, capacity = pairs.current.capacity;
    // The pair, entry and large-body counters start at zero.
    const std::size_t counters = RUBBLE_STATUS_LARGE - RUBBLE_STATUS_PAIRS + 1;
    RUBBLE_TRY(fillRange(c, q.status(), 0u, RUBBLE_STATUS_PAIRS * sizeof(cl_uint),
                         counters * sizeof(cl_uint), profile));
    RUBBLE_TRY(fill(c, bodyCount_, 0u, std::size_t(count) * sizeof(cl_uint), profile));

    // The columns: bounds and mean widths, then each body's entries, sorted by column and by
    // start along the sweep axis.
    RUBBLE_TRY(Dispatch(c, KernelId::GridBounds, profile)
                   .arg(count)
                   .arg(boxes_)
                   .arg(broadFlags_)
                   .arg(partials_)
                   .run(sizes.sortItems, sizes.broadGroup));
    const cl_uint maxCells = cl_uint(1) << gridBits_, sweepBits = sweepBits_;
    RUBBLE_TRY(Dispatch(c, KernelId::GridSetup, profile)
                   .arg(maxCells)
                   .arg(sweepBits)
                   .arg(partials_)
                   .arg(grid_)
                   .run(1, 1));
    RUBBLE_TRY(Dispatch(c, KernelId::GridEntries, profile)
                   .arg(count)
                   .arg(boxes_)
                   .arg(broadFlags_)
                   .arg(grid_)
                   .arg(q.status())
                   .arg(keys_)
                   .arg(values_)
                   .arg(large_)
                   .run(count, sizes.broadGroup));
    RUBBLE_TRY(sort.sort(q, keys_, values_, keysAlt_, valuesAlt_, entries, gridBits_ + sweepBits_,
                         RUBBLE_STATUS_GRID_ENTRIES));

    // Candidate pairs from the columns, then from the planes and the large bodies.
    const std::size_t entryItems = q.strideItems(entries, sizes.broadGroup);
    RUBBLE_TRY(Dispatch(c, KernelId::GatherCellBoxes, profile)
                   .arg(q.status())
                   .arg(values_)
                   .arg(boxes_)
                   .arg(cellBoxes_)
                   .run(entries, sizes.broadGroup));
    const cl_uint joinedCount = joinedCount_, planeCount = planeCount_;
    RUBBLE_TRY(Dispatch(c, KernelId::FindCellPairs, profile)
                   .arg(keys_)
                   .arg(values_)
                   .arg(cellBoxes_)
                   .arg(grid_)
                   .arg(joinedCount)
                   .arg(joined_)
                   .arg(capacity)
                   .arg(pairs.found)
                   .arg(q.status())
                   .run(entryItems, sizes.broadGroup));
    RUBBLE_TRY(Dispatch(c, KernelId::FindLargePairs, profile)
                   .arg(count)
                   .arg(boxes_)
                   .arg(broadFlags_)
                   .arg(planeCount)
                   .arg(planes_)
                   .arg(large_)
                   .arg(joinedCount)
                   .arg(joined_)
                   .arg(capacity)
                   .arg(pairs.found)
                   .arg(q.status())
                   .run(count, sizes.broadGroup));

    // Sorted by (a, b): counted per body, placed, each body's partners sorted.
    const std::size_t pairItems = pairs.strideItems(q);
    RUBBLE_TRY(Dispatch(c, KernelId::CountPairs, profile)
                   .arg(capacity)
                   .arg(q.status())
                   .arg(pairs.found)
                   .arg(bodyCount_)
                   .run(pairItems, sizes.pairGroup));
    RUBBLE_TRY(exclusiveScan(q, bodyCount_, bodyStart_, count));
    RUBBLE_TRY(q.copy(bodyStart_, cursor_, (std::size_t(count) + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(Dispatch(c, KernelId::PlacePairs, profile)
                   .arg(capacity)
                   .arg(q.status())
                   .arg(pairs.found)
                   .arg(cursor_)
                   .arg(pairs.current.pairs)
                   .run(pairItems, sizes.pairGroup));
    RUBBLE_TRY(Dispatch(c, KernelId::SortPairLists, profile)
                   .arg(count)
                   .arg(bodyStart_)
                   .arg(pairs.current.pairs)
                   .run(count, sizes.broadGroup));
    // The count travels with the pairs (last step's set keeps its own). Both words of the set's
    // count go: the first is the pairs found; the second, the entries kept, is the carry's to
    // write at the end of the step (PairStore::keep) before any step reads it, so the status
    // word after the pairs' stands there until then. (A copy of the first word alone leaves
    // Oclgrind seeing the second as never written from then on.)
    return q.copy(q.status(), pairs.current.count, 2 * sizeof(cl_uint),
                  RUBBLE_STATUS_PAIRS * sizeof(cl_uint), 0);
}

Result<std::vector<shared::BodyBox>> SatBroadPhase::downloadBoxes(StageQueue& q,
                                                                  std::uint32_t bodies) const {
    return download<shared::BodyBox>(q.c(), boxes_, bodies);
}

} // namespace rubble::gpu
