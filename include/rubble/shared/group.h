// include/rubble/shared/group.h: totals over a work-group and each work-item's share of a strided
// launch. A kernel whose work-items each add to one global word (a count in the status block, a
// largest change, the next free slot of a list) adds to a __local word instead, and one work-item
// adds the group's total to the global word: one global atomic per group instead of one per
// work-item, so that work-items on different cores do not pass the word's cache line back and
// forth. Each group function holds barriers: every work-item of the group calls it. The split of
// a launch's items (itemRangeItem) compiles on the host too, for its tests.
#pragma once

#include "rubble/shared/cl_compat.h"

// 1 on a CPU device: each work-item of a strided launch takes a run of consecutive items; 0 (a
// GPU) the items of its group one group-width apart (itemRangeItem). A tuning parameter: the host
// derives it from the device (contiguousItems in host/gpu/tuning.h) and passes it with -D.
#ifndef RUBBLE_CONTIGUOUS_ITEMS
#define RUBBLE_CONTIGUOUS_ITEMS 0
#endif

RUBBLE_SHARED_BEGIN

// Work-item `item` of group `group` (of `groups` groups of `size`) in a launch that strides
// through `n` items: from `first` below `end`, `step` apart.
typedef struct ItemRange {
    uint first, end, step;
} ItemRange;

// The group takes a block of consecutive items (`block`, a multiple of the group's size).
// Neighbours in a list (the pairs of one body, sorted together) are then handled by one group.
// Within the block, with `contiguous`, work-item k takes the k-th of `size` equal runs: on a CPU
// device the work-items of a group run one after the other on one core, each reading its run
// front to back, which the core's prefetcher follows (items a group-width apart can be more than
// a page apart). Without, work-item k goes through the block from its k-th item, `size` apart: on
// a GPU adjacent work-items read adjacent items at once. Either way each item is handled by one
// work-item, so the split changes which work-item does the work, not the work.
RUBBLE_FN ItemRange itemRangeItem(uint n, uint groups, uint size, uint group, uint item,
                                  int contiguous) {
    const uint perGroup = (n + groups - 1u) / groups;
    const uint block = (perGroup + size - 1u) / size * size;
    const ulong start = (ulong)group * block;
    ItemRange r;
    if (contiguous) {
        const uint run = block / size;
        const ulong first = start + (ulong)item * run;
        r.first = (uint)(first < n ? first : n);
        r.end = (uint)(first + run < n ? first + run : n);
        r.step = 1u;
    } else {
        const ulong end = start + block;
        r.first = (uint)(start < n ? start : n) + item;
        r.end = (uint)(end < n ? end : n);
        r.step = size;
    }
    return r;
}

RUBBLE_SHARED_END

#ifdef __OPENCL_C_VERSION__

// Zeroes the group's `count` words before the work-items add to them.
static void groupClear(__local uint* words, const uint count) {
    if (get_local_id(0) == 0u)
        for (uint k = 0; k < count; ++k) words[k] = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
}

// After every work-item of the group has added its share: whether this work-item is the one
// that passes the group's words on.
static int groupDone(void) {
    barrier(CLK_LOCAL_MEM_FENCE);
    return get_local_id(0) == 0u;
}

// `n` slots of a run whose global count is *total: the first of this work-item's, the group's
// slots taken together with one atomic. words: two of the group's (its count, its first slot).
static uint groupReserve(__local uint* words, const uint n, __global uint* total) {
    groupClear(words, 1u);
    const uint offset = n > 0u ? atomic_add(&words[0], n) : 0u;
    if (groupDone()) words[1] = words[0] > 0u ? atomic_add(total, words[0]) : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    return words[1] + offset;
}

// This work-item's items of a launch that strides through `n` items (a count the device holds,
// so the launch has a fixed size): `for (p = r.first; p < r.end; p += r.step)`.
static ItemRange itemRange(const uint n) {
    return itemRangeItem(n, (uint)get_num_groups(0), (uint)get_local_size(0),
                         (uint)get_group_id(0), (uint)get_local_id(0), RUBBLE_CONTIGUOUS_ITEMS);
}

#endif
