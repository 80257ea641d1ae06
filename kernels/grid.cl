// kernels/grid.cl: entry points of OpenCL stage 3 (buildGrid): cell keys, a stable LSD radix
// sort of (key, value) pairs, cell ranges; and the exclusive scan the sort and the solver use.
// The CPU twin is buildGrid in host/collision/grid.cpp (a stable counting sort).
#include "rubble/shared/particle.h"

__kernel void computeCellKeys(const uint count, const float inverseCellSize, const uint bits,
                              __global const float4* world, __global uint* keys,
                              __global uint* values) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    keys[i] = cellKeyItem(world[i], inverseCellSize, bits);
    values[i] = i;
}

// The number of keys a sort pass works on: `count`, or the count in a status slot when one is
// named (contacts: the host does not know it), at most `count`.
static uint sortCount(const uint count, __global const uint* status, const uint countSlot) {
    return countSlot < RUBBLE_STATUS_COUNT ? min(status[countSlot], count) : count;
}

// Radix sort, one pass of RUBBLE_SORT_DIGIT_BITS: RUBBLE_SORT_ITEMS work-items each own a
// contiguous chunk of the keys and count its digits; histogram is digit-major, so that its
// exclusive scan gives every (digit, item) its first output slot.
__kernel void sortHistogram(const uint count, __global const uint* status, const uint countSlot,
                            const uint shift, __global const uint* keys,
                            __global uint* histogram) {
    const uint t = get_global_id(0);
    if (t >= RUBBLE_SORT_ITEMS) return;
    const uint n = sortCount(count, status, countSlot);
    const uint chunk = (n + RUBBLE_SORT_ITEMS - 1u) / RUBBLE_SORT_ITEMS;
    uint counts[RUBBLE_SORT_BUCKETS];
    for (uint d = 0; d < RUBBLE_SORT_BUCKETS; ++d) counts[d] = 0;
    const uint begin = min(n, t * chunk), end = min(n, begin + chunk);
    for (uint i = begin; i < end; ++i) ++counts[(keys[i] >> shift) & (RUBBLE_SORT_BUCKETS - 1u)];
    for (uint d = 0; d < RUBBLE_SORT_BUCKETS; ++d) histogram[d * RUBBLE_SORT_ITEMS + t] = counts[d];
}

// Each item moves its chunk, in order, to the slots the scanned histogram gives: stable.
__kernel void sortScatter(const uint count, __global const uint* status, const uint countSlot,
                          const uint shift, __global const uint* keys, __global const uint* values,
                          __global const uint* offsets, __global uint* keysOut,
                          __global uint* valuesOut) {
    const uint t = get_global_id(0);
    if (t >= RUBBLE_SORT_ITEMS) return;
    const uint n = sortCount(count, status, countSlot);
    const uint chunk = (n + RUBBLE_SORT_ITEMS - 1u) / RUBBLE_SORT_ITEMS;
    uint next[RUBBLE_SORT_BUCKETS];
    for (uint d = 0; d < RUBBLE_SORT_BUCKETS; ++d) next[d] = offsets[d * RUBBLE_SORT_ITEMS + t];
    const uint begin = min(n, t * chunk), end = min(n, begin + chunk);
    for (uint i = begin; i < end; ++i) {
        const uint k = keys[i];
        const uint at = next[(k >> shift) & (RUBBLE_SORT_BUCKETS - 1u)]++;
        keysOut[at] = k;
        valuesOut[at] = values[i];
    }
}

// out[i] = in[0] + ... + in[i - 1] for i <= count (out has count + 1 entries). One work-item:
// the arrays scanned here (sort histograms, per-body counts) are small next to the rest.
__kernel void exclusiveScan(const uint count, __global const uint* in, __global uint* out) {
    if (get_global_id(0) != 0) return;
    uint sum = 0;
    for (uint i = 0; i < count; ++i) {
        const uint v = in[i];
        out[i] = sum;
        sum += v;
    }
    out[count] = sum;
}

// cellFirst[k] becomes the first sorted slot whose key is k or more, for every k up to and
// including the cell count: cell k's particles are slots cellFirst[k] to cellFirst[k + 1], and
// the cells k to k + 2 of a row one run from cellFirst[k] to cellFirst[k + 3], two reads and no
// test for empty cells. Each item writes the keys from its predecessor's (excluded) to its own,
// and the last item the keys after its own, so every entry is written once and nothing is
// cleared first. The particles' positions and bodies (tagged with their flags) are copied in
// sorted order for collideParticles, which then reads a cell's particles from consecutive memory.
__kernel void findCellRanges(const uint count, const uint cells, __global const uint* keys,
                             __global const uint* order, __global const float4* world,
                             __global const Particle* particles, __global const uint* flags,
                             __global uint* cellFirst, __global float4* sortedWorld,
                             __global uint* sortedTags) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const uint k = keys[i];
    const uint from = i == 0 ? 0u : keys[i - 1] + 1u;
    for (uint c = from; c <= k; ++c) cellFirst[c] = i;
    if (i + 1 == count)
        for (uint c = k + 1u; c <= cells; ++c) cellFirst[c] = count;
    const uint p = order[i];
    sortedWorld[i] = world[p];
    const uint body = particles[p].body;
    sortedTags[i] = bodyTagItem(body, flags[body]);
}

// Deterministic mode: contacts in the order a stable sort by particle gave (`order`).
__kernel void permuteContacts(__global const uint* status, __global const uint* order,
                              __global const ParticleContact* in, __global ParticleContact* out) {
    const uint n = liveContactsItem(status[RUBBLE_STATUS_CONTACTS], status[RUBBLE_STATUS_CAPACITY]);
    for (uint i = get_global_id(0); i < n; i += get_global_size(0)) out[i] = in[order[i]];
}

// Each contact's sort key and index for one pass of the stable sort of the contacts (`field`,
// RUBBLE_CONTACT_KEY_*): by (particleA, featureB) in deterministic mode, first by featureB
// (`order` unused) then by particleA in the order the first pass left; for projected
// Gauss-Seidel, then by the pair's higher body and its lower one, so that the contacts go by
// (pair, particleA, featureB), the CPU's order (particleContactsToManifolds).
__kernel void contactKeys(__global const uint* status, __global const ParticleContact* contacts,
                          __global const uint* order, const uint field, __global uint* keys,
                          __global uint* values) {
    const uint n = liveContactsItem(status[RUBBLE_STATUS_CONTACTS], status[RUBBLE_STATUS_CAPACITY]);
    for (uint i = get_global_id(0); i < n; i += get_global_size(0)) {
        const uint c = field == RUBBLE_CONTACT_KEY_FEATURE ? i : order[i];
        const ParticleContact x = contacts[c];
        keys[i] = field == RUBBLE_CONTACT_KEY_FEATURE    ? x.featureB
                  : field == RUBBLE_CONTACT_KEY_PARTICLE ? x.particleA
                  : field == RUBBLE_CONTACT_KEY_HIGHER   ? max(x.a, x.b)
                                                         : min(x.a, x.b);
        values[i] = c;
    }
}

// out[i] = value for i < count: clears counters and accumulators. A kernel rather than
// clEnqueueFillBuffer, whose writes Oclgrind 21.10 does not see (it then reports every read of
// the memory as uninitialised).
__kernel void fillWords(const uint count, const uint value, __global uint* out) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    out[i] = value;
}
