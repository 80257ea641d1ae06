// kernels/pgs_still_pairs.cl: entry points that carry the warm-start impulses of still pairs
// (both bodies at rest) into the next step's pair set, as the CPU's storeContactImpulses merges
// them (host/dynamics/pgs.cpp).
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/group.h"
#include "rubble/shared/narrow_phase.h"
#include "rubble/shared/pgs_joint.h"

// The still pairs the next step keeps, at the end of each step (markStillPairs, a scan of the
// chunks' counts, placeStillPairs, carryStillPairs): last step's kept entries (its pairs, then
// the still pairs it carried) whose bodies both stood still in this step's solve, that hold
// impulses and that this step's pairs do not hold, follow this step's pairs in its set, sorted
// by (a, b) among themselves; the pair count's second word becomes the entries kept. So a pair
// of sleeping bodies keeps its impulses until one of them wakes, as the CPU's
// storeContactImpulses merges its still pairs' impulses in, and the wake reaches through the
// sleeping bodies they join (wakeStillPairs). Its cached features are not carried: collideShapes
// reads features from last step's own pairs only, as the CPU's narrow phase keeps those of the
// pairs it collided. Entries past the set's capacity are dropped: their pairs start without a
// warm start.

// Pass 1, RUBBLE_SORT_ITEMS work-items each over a contiguous chunk of last step's entries: marks
// the entries to carry (`carry`) and counts them per chunk.
__kernel void markStillPairs(const uint previousCapacity, __global const uint* previousCount,
                             __global const BodyPairRecord* previousPairs,
                             __global const uint* previousImpulseCount, const uint capacity,
                             __global const uint* pairCount, __global const BodyPairRecord* pairs,
                             __global const JacobiBody* bodies, __global uint* carry,
                             __global uint* chunkCounts, __global uint* status) {
    const uint t = get_global_id(0);
    if (t >= RUBBLE_SORT_ITEMS) return;
    const uint n = keptPairsItem(previousCount, previousCapacity);
    if (t == 0u) status[RUBBLE_STATUS_KEPT] = n;
    const uint current = min(pairCount[0], capacity);
    const uint chunk = (n + RUBBLE_SORT_ITEMS - 1u) / RUBBLE_SORT_ITEMS;
    const uint begin = min(n, t * chunk), end = min(n, begin + chunk);
    uint count = 0u;
    for (uint q = begin; q < end; ++q) {
        const BodyPairRecord pair = previousPairs[q];
        uint keep = previousImpulseCount[q] > 0u &&
                    !(jointInverseMassItem(bodies[pair.a]) > 0.0f) &&
                    !(jointInverseMassItem(bodies[pair.b]) > 0.0f);
        if (keep) keep = findPairItem(pair, current, pairs) == current;
        carry[q] = keep;
        count += keep;
    }
    chunkCounts[t] = count;
}

// Pass 3, the same chunks: `place` becomes the exclusive scan of `carry` over the whole set
// (`chunkStarts`: the scan of the chunks' counts), and its entry n the total.
__kernel void placeStillPairs(const uint previousCapacity, __global const uint* previousCount,
                              __global const uint* carry, __global const uint* chunkStarts,
                              __global uint* place) {
    const uint t = get_global_id(0);
    if (t >= RUBBLE_SORT_ITEMS) return;
    const uint n = keptPairsItem(previousCount, previousCapacity);
    const uint chunk = (n + RUBBLE_SORT_ITEMS - 1u) / RUBBLE_SORT_ITEMS;
    const uint begin = min(n, t * chunk), end = min(n, begin + chunk);
    uint at = chunkStarts[t];
    for (uint q = begin; q < end; ++q) {
        place[q] = at;
        at += carry[q];
    }
    if (t == 0u) place[n] = chunkStarts[RUBBLE_SORT_ITEMS];
}

// Pass 4, one work-item per entry of last step's set (striding): a carried entry goes after this
// step's pairs at its rank among the carried ones. Last step's entries are two sorted runs (its
// pairs, then what it carried), so the rank is the entry's place within its own run plus the
// carried entries of the other run that sort before it.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void carryStillPairs(
    const uint previousCapacity, __global const uint* previousCount,
    __global const BodyPairRecord* previousPairs, __global const uint* previousImpulseCount,
    __global const uint* previousImpulseStart, __global const PgsImpulse* previousImpulses,
    __global const uint* carry, __global const uint* place, const uint capacity,
    __global uint* pairCount, __global BodyPairRecord* pairs, __global uint* impulseCount,
    __global uint* impulseStart, const uint impulseRoom, __global PgsImpulse* impulses,
    __global uint* status) {
    const uint ownRun = min(previousCount[0], previousCapacity);
    const uint n = keptPairsItem(previousCount, previousCapacity);
    const uint current = min(pairCount[0], capacity);
    if (get_global_id(0) == 0u) {
        const uint kept = min(current + place[n], capacity);
        pairCount[1] = kept;
        status[RUBBLE_STATUS_CARRIED] = kept - current;
    }
    const ItemRange r = itemRange(n);
    // The work-item's entries come in (a, b) order within each run: where each sorts in the
    // other run is at or past where the one before it did.
    uint inCarried = ownRun, inOwn = 0u;
    for (uint q = r.first; q < r.end; q += r.step) {
        if (!carry[q]) continue;
        const BodyPairRecord pair = previousPairs[q];
        uint rank;
        if (q < ownRun) {
            inCarried = lowerPairItem(pair, inCarried, n, previousPairs);
            rank = place[q] + place[inCarried] - place[ownRun];
        } else {
            inOwn = lowerPairItem(pair, inOwn, ownRun, previousPairs);
            rank = place[q] - place[ownRun] + place[inOwn];
        }
        const uint at = current + rank;
        if (at >= capacity) continue;
        pairs[at] = pair;
        uint held = min(previousImpulseCount[q], 4u);
        // Its impulses after this step's (the host leaves room for all of last step's).
        const uint start = held > 0u ? atomic_add(&status[RUBBLE_STATUS_IMPULSES], held) : 0u;
        if (start + held > impulseRoom) held = 0u;
        const uint from = held > 0u ? previousImpulseStart[q] : 0u;
        impulseStart[at] = start;
        impulseCount[at] = held;
        for (uint k = 0; k < held; ++k) impulses[start + k] = previousImpulses[from + k];
    }
}
