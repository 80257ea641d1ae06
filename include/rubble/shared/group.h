// include/rubble/shared/group.h: totals over a work-group and each group's block of a strided
// launch, for the kernels only (nothing here is compiled on the host). A kernel whose work-items
// each add to one global word (a count in the status block, a largest change, the next free slot of
// a list) adds to a __local word instead, and one work-item adds the group's total to the global
// word: one global atomic per group instead of one per work-item. On a CPU device, work-items of
// groups running on two cores that update one word move its cache line back and forth between the
// cores: `perf annotate` of debris_16k put 7 % of solvePgs, 8 % of collideShapes and 81 % of
// gridEntries on such atomics (docs/opencl.md). Each function holds barriers: every work-item of
// the group calls it.
#pragma once

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

// A launch that strides through `n` items (a count the device holds, so the launch has a fixed
// size): this work-group takes a block of consecutive items, ending at blockEnd; work-item k of
// the group goes through it from its k-th item (blockFirst), get_local_size(0) apart. Neighbours
// in a list (the pairs of one body, sorted together) are then handled by one group: on a CPU
// device one core, with the bodies they share in its cache; on a GPU adjacent work-items still
// read adjacent items.
static uint blockSize(const uint n) {
    const uint size = (uint)get_local_size(0), groups = (uint)get_num_groups(0);
    return ((n + groups - 1u) / groups + size - 1u) / size * size;
}
static uint blockFirst(const uint n) {
    return min((uint)get_group_id(0) * blockSize(n), n) + (uint)get_local_id(0);
}
static uint blockEnd(const uint n) { return min(((uint)get_group_id(0) + 1u) * blockSize(n), n); }

#endif
