// host/gpu/sort.cpp: dispatch of the radix sort and the scan (kernels/grid.cl).
#include "host/gpu/sort.h"

#include <utility>

namespace rubble::gpu {

Status exclusiveScan(StageQueue& q, const Buffer& in, const Buffer& out, std::uint32_t count) {
    RUBBLE_TRY(Dispatch(q.c(), KernelId::ExclusiveScan, &q.profile())
                   .arg(count)
                   .arg(in)
                   .arg(out)
                   .run(1, 1));
    q.profile().setLastBytes((2 * std::size_t(count) + 1) *
                             sizeof(cl_uint)); // in read, out written
    return {};
}

Status RadixSort::create(StageQueue& q) {
    const Context& c = q.c();
    const std::size_t histogram = RUBBLE_SORT_BUCKETS * c.workSizes().sortItems;
    RUBBLE_TRY(histogram_.reserve(c.context(), histogram * sizeof(cl_uint)));
    return offsets_.reserve(c.context(), (histogram + 1) * sizeof(cl_uint));
}

Status RadixSort::sort(StageQueue& q, Buffer& keys, Buffer& values, Buffer& keysAlt,
                       Buffer& valuesAlt, std::uint32_t count, std::uint32_t bits,
                       std::uint32_t countSlot) {
    const Context& c = q.c();
    const cl_uint n = count, slot = countSlot;
    const cl_uint items = c.workSizes().sortItems;
    const cl_uint buckets = RUBBLE_SORT_BUCKETS * items;
    for (cl_uint shift = 0; shift < bits; shift += RUBBLE_SORT_DIGIT_BITS) {
        RUBBLE_TRY(Dispatch(c, KernelId::SortHistogram, &q.profile())
                       .arg(n)
                       .arg(q.status())
                       .arg(slot)
                       .arg(shift)
                       .arg(keys)
                       .arg(histogram_)
                       .run(items, RUBBLE_GROUP_SCAN));
        RUBBLE_TRY(exclusiveScan(q, histogram_, offsets_, buckets));
        RUBBLE_TRY(Dispatch(c, KernelId::SortScatter, &q.profile())
                       .arg(n)
                       .arg(q.status())
                       .arg(slot)
                       .arg(shift)
                       .arg(keys)
                       .arg(values)
                       .arg(offsets_)
                       .arg(keysAlt)
                       .arg(valuesAlt)
                       .run(items, RUBBLE_GROUP_SCAN));
        std::swap(keys, keysAlt);
        std::swap(values, valuesAlt);
    }
    return {};
}

} // namespace rubble::gpu
