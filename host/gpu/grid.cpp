// host/gpu/grid.cpp: dispatch of OpenCL stage 3, buildGrid (kernels/grid.cl): cell keys, the
// radix sort, cell ranges and the sorted copies of the particles; the CPU twin is buildGrid in
// host/collision/grid.cpp.
#include <utility>

#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::exclusiveScan(const Buffer& in, Buffer& out, std::uint32_t count) {
    RUBBLE_TRY(Dispatch(*context_, KernelId::ExclusiveScan, &profile_)
                   .arg(count)
                   .arg(in)
                   .arg(out)
                   .run(1, 1));
    profile_.setLastBytes((2 * std::size_t(count) + 1) * sizeof(cl_uint)); // in read, out written
    return {};
}

Status Pipeline::radixSort(Buffer& keys, Buffer& values, Buffer& keysAlt, Buffer& valuesAlt,
                           std::uint32_t count, std::uint32_t bits, std::uint32_t countSlot) {
    const cl_uint n = count, slot = countSlot;
    const cl_uint items = context_->workSizes().sortItems;
    const cl_uint buckets = RUBBLE_SORT_BUCKETS * items;
    for (cl_uint shift = 0; shift < bits; shift += RUBBLE_SORT_DIGIT_BITS) {
        RUBBLE_TRY(Dispatch(*context_, KernelId::SortHistogram, &profile_)
                       .arg(n)
                       .arg(status_)
                       .arg(slot)
                       .arg(shift)
                       .arg(keys)
                       .arg(particles_.histogram)
                       .run(items, RUBBLE_GROUP_SCAN));
        RUBBLE_TRY(exclusiveScan(particles_.histogram, particles_.offsets, buckets));
        RUBBLE_TRY(Dispatch(*context_, KernelId::SortScatter, &profile_)
                       .arg(n)
                       .arg(status_)
                       .arg(slot)
                       .arg(shift)
                       .arg(keys)
                       .arg(values)
                       .arg(particles_.offsets)
                       .arg(keysAlt)
                       .arg(valuesAlt)
                       .run(items, RUBBLE_GROUP_SCAN));
        std::swap(keys, keysAlt);
        std::swap(values, valuesAlt);
    }
    return {};
}

Status Pipeline::buildGrid() {
    const cl_uint count = particles_.count, bits = particles_.bits;
    const cl_float inverseCellSize = 1.0f / particles_.cellSize;
    RUBBLE_TRY(Dispatch(*context_, KernelId::ComputeCellKeys, &profile_)
                   .arg(count)
                   .arg(inverseCellSize)
                   .arg(bits)
                   .arg(particles_.world)
                   .arg(particles_.keys)
                   .arg(particles_.values)
                   .run(count, RUBBLE_GROUP_PARTICLES));
    RUBBLE_TRY(radixSort(particles_.keys, particles_.values, particles_.keysAlt,
                         particles_.valuesAlt, count, bits));
    const cl_uint cells = cl_uint(1) << bits;
    // No particles: every cell starts (and ends) at slot 0.
    if (count == 0)
        return fill(*context_, particles_.cellFirst, 0u, (std::size_t(cells) + 1) * sizeof(cl_uint),
                    &profile_);
    return Dispatch(*context_, KernelId::FindCellRanges, &profile_)
        .arg(count)
        .arg(cells)
        .arg(particles_.keys)
        .arg(particles_.values)
        .arg(particles_.world)
        .arg(particles_.records)
        .arg(bodies_.flags)
        .arg(particles_.cellFirst)
        .arg(particles_.sortedWorld)
        .arg(particles_.sortedTags)
        .run(count, RUBBLE_GROUP_PARTICLES);
}

} // namespace rubble::gpu
