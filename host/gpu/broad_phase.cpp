// host/gpu/broad_phase.cpp: dispatch of the SAT broad phase on the device (kernels/
// broad_phase.cl): computeAabbs, then findPairs by sweep and prune in columns with the pairs
// sorted by (a, b). The CPU twin is SatCollision::broadPhase and findPairs (host/collision/).
#include <algorithm>
#include <cstdio>

#include "host/core/assert.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::broadPhase(float dt) {
    RUBBLE_TRY(computeAabbs(dt));
    return findPairs();
}

Status Pipeline::computeAabbs(float dt) {
    RUBBLE_ASSERT(sat_.enabled);
    const cl_uint count = bodies_.count;
    const cl_float step = dt;
    return Dispatch(*context_, KernelId::ComputeAabbs, &profile_)
        .arg(count)
        .arg(step)
        .arg(sat_.shapes)
        .arg(sat_.shapeOf)
        .arg(bodies_.poses)
        .arg(bodies_.velocities)
        .arg(bodies_.flags)
        .arg(sat_.boxes)
        .arg(sat_.spin)
        .arg(sat_.broadFlags)
        .run(count, context_->workSizes().broadGroup);
}

Status Pipeline::findPairs() {
    RUBBLE_ASSERT(sat_.enabled);
    const Context& c = *context_;
    const WorkSizes& sizes = c.workSizes();
    const cl_uint count = bodies_.count;
    const cl_uint entries = 4 * count, capacity = sat_.current.capacity;
    // The pair, entry and large-body counters start at zero.
    const std::size_t counters = RUBBLE_STATUS_LARGE - RUBBLE_STATUS_PAIRS + 1;
    RUBBLE_TRY(fillRange(c, status_, 0u, RUBBLE_STATUS_PAIRS * sizeof(cl_uint),
                         counters * sizeof(cl_uint), &profile_));
    RUBBLE_TRY(fill(c, sat_.bodyCount, 0u, std::size_t(count) * sizeof(cl_uint), &profile_));

    // The columns: bounds and mean widths, then each body's entries, sorted by column and by
    // start along the sweep axis.
    RUBBLE_TRY(Dispatch(c, KernelId::GridBounds, &profile_)
                   .arg(count)
                   .arg(sat_.boxes)
                   .arg(sat_.broadFlags)
                   .arg(sat_.partials)
                   .run(sizes.sortItems, sizes.broadGroup));
    const cl_uint maxCells = cl_uint(1) << sat_.gridBits, sweepBits = sat_.sweepBits;
    RUBBLE_TRY(Dispatch(c, KernelId::GridSetup, &profile_)
                   .arg(maxCells)
                   .arg(sweepBits)
                   .arg(sat_.partials)
                   .arg(sat_.grid)
                   .run(1, 1));
    RUBBLE_TRY(Dispatch(c, KernelId::GridEntries, &profile_)
                   .arg(count)
                   .arg(sat_.boxes)
                   .arg(sat_.broadFlags)
                   .arg(sat_.grid)
                   .arg(status_)
                   .arg(sat_.keys)
                   .arg(sat_.values)
                   .arg(sat_.large)
                   .run(count, sizes.broadGroup));
    RUBBLE_TRY(radixSort(sat_.keys, sat_.values, sat_.keysAlt, sat_.valuesAlt, entries,
                         sat_.gridBits + sat_.sweepBits, RUBBLE_STATUS_GRID_ENTRIES));

    // Candidate pairs from the columns, then from the planes and the large bodies.
    const std::size_t entryItems = strideItems(entries, sizes.broadGroup);
    RUBBLE_TRY(Dispatch(c, KernelId::GatherCellBoxes, &profile_)
                   .arg(status_)
                   .arg(sat_.values)
                   .arg(sat_.boxes)
                   .arg(sat_.cellBoxes)
                   .run(entries, sizes.broadGroup));
    const cl_uint joinedCount = sat_.joinedCount, planeCount = sat_.planeCount;
    RUBBLE_TRY(Dispatch(c, KernelId::FindCellPairs, &profile_)
                   .arg(sat_.keys)
                   .arg(sat_.values)
                   .arg(sat_.cellBoxes)
                   .arg(sat_.grid)
                   .arg(joinedCount)
                   .arg(sat_.joined)
                   .arg(capacity)
                   .arg(sat_.found)
                   .arg(status_)
                   .run(entryItems, sizes.broadGroup));
    RUBBLE_TRY(Dispatch(c, KernelId::FindLargePairs, &profile_)
                   .arg(count)
                   .arg(sat_.boxes)
                   .arg(sat_.broadFlags)
                   .arg(planeCount)
                   .arg(sat_.planes)
                   .arg(sat_.large)
                   .arg(joinedCount)
                   .arg(sat_.joined)
                   .arg(capacity)
                   .arg(sat_.found)
                   .arg(status_)
                   .run(count, sizes.broadGroup));

    // Sorted by (a, b): counted per body, placed, each body's partners sorted.
    const std::size_t pairItems = pairStrideItems();
    RUBBLE_TRY(Dispatch(c, KernelId::CountPairs, &profile_)
                   .arg(capacity)
                   .arg(status_)
                   .arg(sat_.found)
                   .arg(sat_.bodyCount)
                   .run(pairItems, sizes.pairGroup));
    RUBBLE_TRY(exclusiveScan(sat_.bodyCount, sat_.bodyStart, count));
    const std::size_t starts = (std::size_t(count) + 1) * sizeof(cl_uint);
    RUBBLE_CL_CHECK(clEnqueueCopyBuffer(c.queue(), sat_.bodyStart.mem(), sat_.cursor.mem(), 0, 0,
                                        starts, 0, nullptr,
                                        profile_.transfer(Transfer::Copy, starts)));
    RUBBLE_TRY(Dispatch(c, KernelId::PlacePairs, &profile_)
                   .arg(capacity)
                   .arg(status_)
                   .arg(sat_.found)
                   .arg(sat_.cursor)
                   .arg(sat_.current.pairs)
                   .run(pairItems, sizes.pairGroup));
    RUBBLE_TRY(Dispatch(c, KernelId::SortPairLists, &profile_)
                   .arg(count)
                   .arg(sat_.bodyStart)
                   .arg(sat_.current.pairs)
                   .run(count, sizes.broadGroup));
    // The count travels with the pairs (last step's set keeps its own).
    RUBBLE_CL_CHECK(clEnqueueCopyBuffer(
        c.queue(), status_.mem(), sat_.current.count.mem(), RUBBLE_STATUS_PAIRS * sizeof(cl_uint),
        0, sizeof(cl_uint), 0, nullptr, profile_.transfer(Transfer::Copy, sizeof(cl_uint))));
    return {};
}

Result<std::uint32_t> Pipeline::readPairCount() {
    for (;;) {
        Result<DeviceStatus> st = readStatus();
        RUBBLE_TRY(st);
        const std::uint32_t found = st->pairs;
        if (found <= sat_.current.capacity) return found;
        const std::uint32_t grown = found + found / 2;
        std::fprintf(stderr,
                     "rubble: pair overflow (%u pairs, room for %u): buffers grown to "
                     "%u and the pairs found again\n",
                     found, sat_.current.capacity, grown);
        RUBBLE_TRY(setPairCapacity(grown));
        RUBBLE_TRY(findPairs());
    }
}

} // namespace rubble::gpu
