// kernels/pgs.cl: entry points of projected Gauss-Seidel on the device: the rows of each pair's
// manifold (buildPgsRows), then, one launch per color (no two elements of a color share a body
// that moves), the warm start, the velocity sweeps and the split position pass; the pushes
// applied after integratePositions. The math is in rubble/shared/pgs_row.h; the CPU twin is
// PgsSolver (host/dynamics/pgs_solver.cpp).
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/group.h"
#include "rubble/shared/narrow_phase.h"
#include "rubble/shared/pgs_joint.h"

// One work-item per pair (striding), after the narrow phase: the pair's summary word for the
// coloring (its point count and which bodies move; 0 when it gets no rows), and what it keeps
// for the next step's warm start when it gets no rows: a pair whose bodies both stand still
// keeps last step's impulses as they were (an island woken later starts from them), a pair
// without points none. A point deep enough to push marks its pair's moving bodies for the split
// position pass, and the status block, so that the host knows before it enqueues the pass; a
// point that will have a bounce speed (pointBounceItem, as its row will) marks the status block
// for the restitution pass.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
summarizePairs(const uint capacity, __global const uint* pairCount,
               __global const BodyPairRecord* pairs, __global const ContactManifold* manifolds,
               __global const JacobiBody* bodies, __global const BodyPose* poses,
               __global const BodyVelocity* velocities, __global const BodyVelocity* approach,
               __global const float4* surfaces, const float baumgarte, const float slop,
               const float dt, const uint warmStart, const uint previousCapacity,
               __global const uint* previousCount, __global const uint* previousOf,
               __global const uint* previousImpulseCount,
               __global const PgsImpulse* previousImpulses, __global uint* pairRows,
               __global uint* impulseCount, __global PgsImpulse* kept, __global uint* pushed,
               __global uint* status) {
    const uint n = min(pairCount[0], capacity);
    // Last step's entries: its pairs and the still pairs it carried (markStillPairs).
    const uint previous = warmStart ? keptPairsItem(previousCount, previousCapacity) : 0u;
    const ItemRange r = itemRange(n);
    for (uint p = r.first; p < r.end; p += r.step) {
        const uint count = manifolds[p].count;
        const BodyPairRecord pair = pairs[p];
        const uint movesA = jointInverseMassItem(bodies[pair.a]) > 0.0f;
        const uint movesB = jointInverseMassItem(bodies[pair.b]) > 0.0f;
        if (count > 0u && (movesA || movesB)) {
            pairRows[p] = count | (movesA ? RUBBLE_PGS_MOVES_A : 0u) |
                          (movesB ? RUBBLE_PGS_MOVES_B : 0u);
            impulseCount[p] = count;
            int pushes = 0;
            for (uint k = 0; k < count; ++k)
                pushes |=
                    pgsNormalTargetItem(manifolds[p].points[k].w, baumgarte, slop, dt).push > 0.0f;
            if (pushes) {
                if (movesA) pushed[pair.a] = 1u;
                if (movesB) pushed[pair.b] = 1u;
                status[RUBBLE_STATUS_PUSHED] = 1u;
            }
            // A pair of moving bodies this far apart in mass: the layer pass runs (layerPgs
            // leaves out jointed bodies).
            const float ia = jointInverseMassItem(bodies[pair.a]);
            const float ib = jointInverseMassItem(bodies[pair.b]);
            if (heavyOverItem(ia, ib) || heavyOverItem(ib, ia)) status[RUBBLE_STATUS_LAYERS] = 1u;
            const float restitution = fmax(surfaces[pair.a].y, surfaces[pair.b].y);
            if (restitution > 0.0f) {
                const float4 xA = poses[pair.a].position, xB = poses[pair.b].position;
                const BodyVelocity va = velocities[pair.a], vb = velocities[pair.b];
                const BodyVelocity aa = approach[pair.a], ab = approach[pair.b];
                const float4 normal = manifolds[p].normal;
                int bounces = 0;
                for (uint k = 0; k < count; ++k) {
                    const float4 point = manifolds[p].points[k];
                    const Bounce b =
                        pointBounceItem(pgsArmItem(point, xA), pgsArmItem(point, xB), normal,
                                        point.w, va, vb, aa, ab, restitution, dt);
                    bounces |= b.speed > 0.0f;
                }
                if (bounces) status[RUBBLE_STATUS_BOUNCES] = 1u;
            }
            continue;
        }
        pairRows[p] = 0u;
        uint keep = 0u;
        if (count > 0u) {
            const uint q = previousOf[p];
            keep = q < previous ? min(previousImpulseCount[q], 4u) : 0u;
            for (uint k = 0; k < keep; ++k) kept[4u * p + k] = previousImpulses[4u * q + k];
        }
        impulseCount[p] = keep;
    }
}

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
    __global const PgsImpulse* previousImpulses, __global const uint* carry,
    __global const uint* place, const uint capacity,
    __global uint* pairCount, __global BodyPairRecord* pairs, __global uint* impulseCount,
    __global PgsImpulse* impulses, __global uint* status) {
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
        const uint held = min(previousImpulseCount[q], 4u);
        impulseCount[at] = held;
        for (uint k = 0; k < held; ++k) impulses[4u * at + k] = previousImpulses[4u * q + k];
    }
}

// One work-item per pair with rows, in pair order (`order`: the index of its element): the
// rows of the pair's manifold points where its element places them (PgsElement: point k's normal
// row, friction rows and impulses at normal[k]), warm-started from last step's impulses of the
// same pair (warmStartMatchItem), and the points' keys for the next step (their impulses are
// filled in by the last sweep).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
buildPgsRows(const uint count, __global const uint* order, __global const PgsElement* elements,
             __global const ContactManifold* manifolds, __global const BodyPose* poses,
             __global const BodyVelocity* velocities, __global const BodyVelocity* approach,
             __global const JacobiBody* bodies, __global const float4* surfaces,
             const float baumgarte, const float slop,
             const float dt, const uint warmStart, const uint previousCapacity,
             __global const uint* previousCount, __global const uint* previousOf,
             __global const uint* previousImpulseCount,
             __global const PgsImpulse* previousImpulses, __global PgsNormalRow* normalRows,
             __global PgsFrictionRows* frictionRows, __global float4* impulses,
             __global PgsImpulse* kept) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const PgsElement e = elements[order[i]];
    const uint p = e.id, a = e.a, b = e.b;
    const uint points = e.rows & RUBBLE_PGS_POINTS;
    const uint previous = warmStart ? keptPairsItem(previousCount, previousCapacity) : 0u;
    const uint q = previousOf[p];
    const uint oldCount = q < previous ? min(previousImpulseCount[q], 4u) : 0u;
    const ContactManifold m = manifolds[p];
    const JacobiBody ja = bodies[a], jb = bodies[b];
    const float ima = jointInverseMassItem(ja), imb = jointInverseMassItem(jb);
    const float4 sa = surfaces[a], sb = surfaces[b];
    const float friction = sqrt(sa.x * sb.x);
    const float restitution = fmax(sa.y, sb.y);
    const BodyPose pa = poses[a], pb = poses[b];
    const BodyVelocity va = velocities[a], vb = velocities[b];
    const BodyVelocity aa = approach[a], ab = approach[b];
    const float4 fixedTangent = perpendicularItem(m.normal);
    // The keys first: they choose which old point each new one takes its impulses from.
    PgsImpulse keys[4], old[4];
    for (uint k = 0; k < points; ++k) {
        const float4 point = m.points[k];
        const float4 rA = sub4(vec4(point.x, point.y, point.z),
                               vec4(pa.position.x, pa.position.y, pa.position.z));
        keys[k].pointInA = quatRotateInverse(pa.orientation, rA);
        keys[k].feature = m.features[k];
    }
    for (uint o = 0; o < oldCount; ++o) old[o] = previousImpulses[4u * q + o];
    const WarmStartMatch match = warmStartMatchItem(keys, points, old, oldCount);
    for (uint k = 0; k < points; ++k) {
        const float4 point = m.points[k];
        const PgsContactRow row = pgsContactRowItem(
            point, point.w, m.normal, pa.position, pb.position, va, vb, aa, ab, ima, imb,
            ja.inverseInertiaWorld, jb.inverseInertiaWorld, friction, restitution, baumgarte,
            slop, dt, fixedTangent);
        float4 start = make4(0.0f, 0.0f, 0.0f, 0.0f);
        if (match.from[k] >= 0) {
            const PgsImpulse from = old[match.from[k]];
            start.x = from.normal;
            start.y = dot3(from.friction, row.friction.tangent[0]);
            start.z = dot3(from.friction, row.friction.tangent[1]);
        }
        normalRows[e.normal[k]] = row.normal;
        frictionRows[e.normal[k]] = row.friction;
        impulses[e.normal[k]] = start;
        // What the next step starts from if no sweep runs; the last sweep overwrites it.
        PgsImpulse key = keys[k];
        key.normal = start.x;
        key.friction = add4(scale4(row.friction.tangent[0], start.y),
                            scale4(row.friction.tangent[1], start.z));
        key.pad0 = key.pad1 = 0u;
        kept[4u * p + k] = key;
    }
}

// The velocities of an element's two bodies; a body that does not move is read (it may be a
// moving obstacle) but never written, since other elements of the color may share it.
static BodyVelocityPair loadPair(const uint a, const uint b, __global const BodyVelocity* v) {
    BodyVelocityPair p;
    p.a = v[a];
    p.b = v[b];
    return p;
}
static void storePair(const BodyVelocityPair p, const uint a, const uint b, const uint summary,
                      __global BodyVelocity* v) {
    if (summary & RUBBLE_PGS_MOVES_A) v[a] = p.a;
    if (summary & RUBBLE_PGS_MOVES_B) v[b] = p.b;
}

// Which of a joint's bodies move in this step's solve (the host colors joints over every
// dynamic body, asleep or not).
static uint jointMoves(const JacobiBody ja, const JacobiBody jb) {
    return (jointInverseMassItem(ja) > 0.0f ? RUBBLE_PGS_MOVES_A : 0u) |
           (jointInverseMassItem(jb) > 0.0f ? RUBBLE_PGS_MOVES_B : 0u);
}

// The elements of one launch, by its `mode`: RUBBLE_PGS_PER_ITEM, one per work-item (a color);
// RUBBLE_PGS_SERIAL, all of them in order on work-item 0 (the serial tail: the last colors, too
// small to be worth a launch each; Gauss-Seidel in color order); RUBBLE_PGS_BLOCKS, block g's
// (blockStarts[g] to blockStarts[g + 1]) in order on work-item 0 of group g.
static uint elementsBegin(const uint count, const uint mode, __global const uint* blockStarts) {
    if (mode == RUBBLE_PGS_BLOCKS) return get_local_id(0) == 0u ? blockStarts[get_group_id(0)] : 0u;
    if (mode == RUBBLE_PGS_SERIAL) return 0u;
    return min((uint)get_global_id(0), count);
}
static uint elementsEnd(const uint count, const uint mode, __global const uint* blockStarts) {
    if (mode == RUBBLE_PGS_BLOCKS)
        return get_local_id(0) == 0u ? min(blockStarts[get_group_id(0) + 1u], count) : 0u;
    if (mode == RUBBLE_PGS_SERIAL) return get_global_id(0) == 0u ? count : 0u;
    return min((uint)get_global_id(0) + 1u, count);
}

// Which rows of an element a pass over it solves (`part` of solveElement), and of which of its
// points (`slot`: one, or all).
#define RUBBLE_PGS_ALL_SLOTS 0xffu
#define RUBBLE_PGS_NORMALS 1u
#define RUBBLE_PGS_FRICTION 2u

// The first point and the end of the points a pass over an element of `points` points takes.
static uint slotFrom(const uint slot) { return slot == RUBBLE_PGS_ALL_SLOTS ? 0u : slot; }
static uint slotEnd(const uint points, const uint slot) {
    return slot == RUBBLE_PGS_ALL_SLOTS ? points : min(slot + 1u, points);
}

// A launch's passes over its elements for the rows of one kind: a block's go through every
// element's first point, then every second point, ... (the CPU's row order,
// interleaveContactRows: in a block elements share bodies, so the order is the solver's), a
// color's take each element whole in one pass (its elements share no body, so any order gives
// the same bits). A block makes as many as its elements' most points, which the host writes
// after the blocks' starts (colorPgs): one for a block of one-point elements (particle contacts).
static uint slotPasses(const uint mode, __global const uint* blockStarts) {
    return mode == RUBBLE_PGS_BLOCKS ? blockStarts[get_num_groups(0) + 1u + get_group_id(0)] : 1u;
}
static uint passSlot(const uint mode, const uint pass) {
    return mode == RUBBLE_PGS_BLOCKS ? pass : RUBBLE_PGS_ALL_SLOTS;
}

// Every block takes its friction rows and its warm start by point, as one block does (unless
// built with -DRUBBLE_PGS_BLOCKS_BY_POINT=0, `rubble run --build-options`): a block then goes
// through every row in the CPU's order and only the elements between blocks differ. On
// debris_64k's five seeds that leaves as many crates moving at step 300 as the CPU (median 21;
// 32 by element) and the deepest crate 9.5 mm (10.0 by element); with the rows laid out by
// point it is also the faster order (debris_16k solvePgs 12.3 against 14.1 ms/step):
// docs/opencl.md, "debris_64k's edge columns" and "Friction rows where the normal rows are".
#ifndef RUBBLE_PGS_BLOCKS_BY_POINT
#define RUBBLE_PGS_BLOCKS_BY_POINT 1
#endif

// Whether a launch's blocks take their friction rows and warm start by point: every block with
// RUBBLE_PGS_BLOCKS_BY_POINT, else a launch of one block (the whole step's elements in order on
// one work-item, as the CPU's sweeps go).
static int byPoint(const uint mode) {
#if RUBBLE_PGS_BLOCKS_BY_POINT
    return mode == RUBBLE_PGS_BLOCKS;
#else
    return mode == RUBBLE_PGS_BLOCKS && get_num_groups(0) == 1u;
#endif
}

// Warm start of one element, or of one of its points (`slot`, as solveElement's): a pair's
// points apply their accumulated impulses (normal, then the two friction rows), as
// warmStartContacts does; a joint its blocks' (warmStartJoints), with the first point's.
static void warmStartElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                             __global const PgsFrictionRows* frictionRows,
                             __global const float4* impulses, __global const PgsJoint* joints,
                             __global const PgsJointRow* jointRows,
                             __global const JacobiBody* bodies,
                             __global BodyVelocity* velocities, const uint slot) {
    const uint from = slotFrom(slot), to = slotEnd(e.rows & RUBBLE_PGS_POINTS, slot);
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) {
        if (from > 0u) return;
    } else if (from >= to) {
        return;
    }
    BodyVelocityPair v = loadPair(e.a, e.b, velocities);
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) {
        const uint j = e.id & ~RUBBLE_PGS_JOINT_ELEMENT;
        const JacobiBody ja = bodies[e.a], jb = bodies[e.b];
        v = warmStartJointItem(v, joints[j], jointRows[j], ja, jb);
        storePair(v, e.a, e.b, jointMoves(ja, jb), velocities);
        return;
    }
    for (uint k = from; k < to; ++k) {
        const float4 l = impulses[e.normal[k]];
        if (l.x != 0.0f) {
            const PgsNormalRow r = normalRows[e.normal[k]];
            v = applyPgsRowItem(v, r.normal, r.turnA, r.turnB, r.speeds.z, r.speeds.w, l.x);
        }
        if (l.y == 0.0f && l.z == 0.0f) continue;
        const PgsFrictionRows f = frictionRows[e.normal[k]];
        const float ima = f.inverseMass.x, imb = f.inverseMass.y;
        if (l.y != 0.0f) v = applyPgsRowItem(v, f.tangent[0], f.turnA[0], f.turnB[0], ima, imb, l.y);
        if (l.z != 0.0f) v = applyPgsRowItem(v, f.tangent[1], f.turnA[1], f.turnB[1], ima, imb, l.z);
    }
    storePair(v, e.a, e.b, e.rows, velocities);
}

// Warm start, one launch (a color, the serial tail or the blocks): element by element, or by
// point (byPoint: the CPU's order, warmStartContacts goes through the interleaved rows).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
warmStartPgs(const uint first, const uint count, const uint mode,
             __global const PgsElement* elements, __global const uint* blockStarts,
             __global const PgsNormalRow* normalRows,
             __global const PgsFrictionRows* frictionRows, __global const float4* impulses,
             __global const PgsJoint* joints, __global const PgsJointRow* jointRows,
             __global const JacobiBody* bodies, __global BodyVelocity* velocities) {
    const uint end = elementsEnd(count, mode, blockStarts);
    const uint passes = byPoint(mode) ? slotPasses(mode, blockStarts) : 1u;
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = elementsBegin(count, mode, blockStarts); i < end; ++i)
            warmStartElement(elements[first + i], normalRows, frictionRows, impulses, joints,
                             jointRows, bodies, velocities,
                             byPoint(mode) ? pass : RUBBLE_PGS_ALL_SLOTS);
}

// solveElement and pushElement are called from three places each (a color's loop, a block's
// passes, the friction pass or pushPgs), and PoCL's LLVM kept them calls: inlined, with `part`,
// `slot` and `backward` constants at each place, the solve stage took 13% less time on
// debris_16k (docs/opencl.md, "Inlining the sweep"), for about 2 s more of the program's first
// build.
#define RUBBLE_PGS_INLINE static inline __attribute__((always_inline))

// The point a pass over points from..to - 1 visits n-th: in order, or last to first.
static uint visitedPoint(const uint n, const uint from, const uint to, const int reversed) {
    return reversed ? from + to - 1u - n : n;
}

// Point k of a pair's element, on the velocities `v` and its impulses `l` (x normal, y and z
// friction): its normal row (part RUBBLE_PGS_NORMALS), then its friction pair bounded by the
// normal impulse (RUBBLE_PGS_FRICTION), whose last sweep keeps the impulses for the next step's
// warm start. Returns the largest |change|, N s.
RUBBLE_PGS_INLINE float solvePoint(const PgsElement e, const uint k, const uint part,
                                   __global const PgsNormalRow* normalRows,
                                   __global const PgsFrictionRows* frictionRows,
                                   const float relaxation, const uint lastSweep,
                                   __global PgsImpulse* kept, BodyVelocityPair* v, float4* l) {
    float residual = 0.0f;
    if (part & RUBBLE_PGS_NORMALS) {
        const PgsNormalRow r = normalRows[e.normal[k]];
        const PgsUpdate u = solvePgsNormalItem(r, *v, r.speeds.x, l->x, relaxation);
        *v = u.v;
        l->x = u.accumulated;
        residual = fmax(residual, fabs(u.applied));
    }
    if (!(part & RUBBLE_PGS_FRICTION)) return residual;
    const PgsFrictionRows r = frictionRows[e.normal[k]];
    const PgsFrictionUpdate u = solvePgsFrictionItem(r, *v, l->x, l->y, l->z, relaxation);
    *v = u.v;
    l->y = u.impulse.x;
    l->z = u.impulse.y;
    residual = fmax(residual, u.impulse.z);
    if (lastSweep) {
        kept[4u * e.id + k].normal = l->x;
        kept[4u * e.id + k].friction = add4(scale4(r.tangent[0], l->y), scale4(r.tangent[1], l->z));
    }
    return residual;
}

// One velocity sweep of one element, or of one part of it: a joint's blocks
// (solveJointVelocity) with the normal rows; a pair's normal rows, then its points' friction
// pairs (bounded by this sweep's normal impulses). A color solves both parts of each element in
// turn; a block solves every element's normal rows, then every element's friction rows, as
// solveContactSweep does. The last sweep's friction part also writes the impulses kept for the
// next step's warm start. Returns the largest |change|, N s.
//
// A color's element (slot RUBBLE_PGS_ALL_SLOTS) goes through its points last to first when
// `backward` (the odd sweeps), and through its normal rows RUBBLE_PGS_ELEMENT_NORMAL_PASSES
// times before its friction rows. Taken whole and always first to last, the few sweeps of a step
// leave a manifold's first point carrying more than its share (its order is the clipping's: the
// same corner of every crate in a column), and a column leans toward that corner a little every
// step until it sleeps or falls: pyramid_20 colored leaned 9.5 cm at the top, and reversing the
// order leaned it the other way. (A block's passes interleave the points of all its elements,
// as the CPU's sweep does, which leans far less: docs/opencl.md, "The colored sweep".)
#define RUBBLE_PGS_ELEMENT_NORMAL_PASSES 2u
RUBBLE_PGS_INLINE float solveElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                                     __global const PgsFrictionRows* frictionRows,
                                     __global float4* impulses, __global const PgsJoint* joints,
                                     __global PgsJointRow* jointRows,
                                     __global const JacobiBody* bodies,
                                     __global BodyVelocity* velocities, const float relaxation,
                                     const uint lastSweep, __global PgsImpulse* kept,
                                     const uint part, const uint slot, const uint backward) {
    // One point (slot < 4) or all of them (RUBBLE_PGS_ALL_SLOTS). A joint's blocks go with the
    // normal rows of the pass that starts at the first point (a color's, or a block's pass over
    // every element's first point).
    const uint from = slotFrom(slot), to = slotEnd(e.rows & RUBBLE_PGS_POINTS, slot);
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) {
        if (!(part & RUBBLE_PGS_NORMALS) || from > 0u) return 0.0f;
    } else if (from >= to) {
        return 0.0f;
    }
    BodyVelocityPair v = loadPair(e.a, e.b, velocities);
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) {
        const uint j = e.id & ~RUBBLE_PGS_JOINT_ELEMENT;
        const JacobiBody ja = bodies[e.a], jb = bodies[e.b];
        const PgsJointUpdate u = solveJointItem(v, joints[j], jointRows[j], ja, jb, relaxation);
        storePair(u.v, e.a, e.b, jointMoves(ja, jb), velocities);
        jointRows[j].pointImpulse = vec4(u.pointImpulse.x, u.pointImpulse.y, u.pointImpulse.z);
        jointRows[j].turnImpulse = u.turnImpulse;
        return u.pointImpulse.w;
    }
    // A block's pass: one point, its impulses in a scalar.
    if (slot != RUBBLE_PGS_ALL_SLOTS) {
        float4 l = impulses[e.normal[slot]];
        const float residual = solvePoint(e, slot, part, normalRows, frictionRows, relaxation,
                                          lastSweep, kept, &v, &l);
        if (part & RUBBLE_PGS_FRICTION)
            impulses[e.normal[slot]] = l;
        else
            impulses[e.normal[slot]].x = l.x;
        storePair(v, e.a, e.b, e.rows, velocities);
        return residual;
    }
    // A color's element: all its points, twice through the normal rows when it has several.
    float residual = 0.0f;
    float4 l[4];
    for (uint k = from; k < to; ++k) l[k] = impulses[e.normal[k]];
    const uint normalPasses =
        (part & RUBBLE_PGS_NORMALS) ? (to - from > 1u ? RUBBLE_PGS_ELEMENT_NORMAL_PASSES : 1u) : 0u;
    for (uint pass = 0u; pass < normalPasses; ++pass)
        for (uint n = from; n < to; ++n) {
            const uint k = visitedPoint(n, from, to, backward);
            residual = fmax(residual, solvePoint(e, k, RUBBLE_PGS_NORMALS, normalRows, frictionRows,
                                                 relaxation, lastSweep, kept, &v, &l[k]));
        }
    if (part & RUBBLE_PGS_FRICTION)
        for (uint n = from; n < to; ++n) {
            const uint k = visitedPoint(n, from, to, backward);
            residual = fmax(residual, solvePoint(e, k, RUBBLE_PGS_FRICTION, normalRows,
                                                 frictionRows, relaxation, lastSweep, kept, &v,
                                                 &l[k]));
        }
    for (uint k = from; k < to; ++k) {
        if (part & RUBBLE_PGS_FRICTION)
            impulses[e.normal[k]] = l[k];
        else
            impulses[e.normal[k]].x = l[k].x;
    }
    storePair(v, e.a, e.b, e.rows, velocities);
    return residual;
}

// One sweep of the split position pass for one element, or for one of its points (`slot`, as
// solveElement's): the normal rows that push, and those that touch a body a push moves, on the
// push velocities toward the rows' push speeds (their accumulated push impulses in w of each
// impulse record, zero when built); joints are projected after integratePositions instead.
// Returns the largest |change|, N s.
RUBBLE_PGS_INLINE float pushElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                                    __global float4* impulses, __global const uint* pushed,
                                    __global BodyVelocity* push, const float relaxation,
                                    const uint slot) {
    const uint from = slotFrom(slot), to = slotEnd(e.rows & RUBBLE_PGS_POINTS, slot);
    if ((e.id & RUBBLE_PGS_JOINT_ELEMENT) || from >= to) return 0.0f;
    // A row that pushes, or bounces, marked its moving bodies: with neither marked every row
    // below is passed over and the velocities go back unchanged, so nothing is read or written.
    if (!pushed[e.a] && !pushed[e.b]) return 0.0f;
    BodyVelocityPair v = loadPair(e.a, e.b, push);
    float residual = 0.0f;
    for (uint k = from; k < to; ++k) {
        // Every row of the element, at its push speed (a row that bounces aims at its lift too:
        // markBounces wrote the target).
        const PgsNormalRow r = normalRows[e.normal[k]];
        float4 l = impulses[e.normal[k]];
        const PgsUpdate u = solvePgsNormalItem(r, v, r.speeds.y, l.w, relaxation);
        v = u.v;
        l.w = u.accumulated;
        impulses[e.normal[k]] = l;
        residual = fmax(residual, fabs(u.applied));
    }
    storePair(v, e.a, e.b, e.rows, push);
    return residual;
}

// One velocity sweep, one launch (a color, the serial tail or the blocks); the last sweep's
// largest |change| goes to the status block. The split position pass's sweep of the same number
// runs in the same launch (pushSweep; RUBBLE_PGS_NO_PUSH when no row pushes): it reads the same
// rows but its own velocities and impulses, so the two passes do not see each other, as on the
// CPU, where it runs after the velocity solve. A push sweep after one whose largest change was
// within RUBBLE_PUSH_TOLERANCE does nothing: the pass has converged.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
solvePgs(const uint first, const uint count, const uint mode,
         __global const PgsElement* elements, __global const uint* blockStarts,
         __global const PgsNormalRow* normalRows,
         __global const PgsFrictionRows* frictionRows, __global float4* impulses,
         __global const PgsJoint* joints, __global PgsJointRow* jointRows,
         __global const JacobiBody* bodies, __global BodyVelocity* velocities,
         const float relaxation, const uint lastSweep, const uint sweep,
         __global PgsImpulse* kept, __global uint* status, const uint pushSweep,
         __global const uint* pushed,
         __global BodyVelocity* push, __global uint* sweepResidual) {
    const uint end = elementsEnd(count, mode, blockStarts);
    const int pushes = pushSweep != RUBBLE_PGS_NO_PUSH &&
                       (pushSweep == 0u ||
                        as_float(sweepResidual[pushSweep - 1u]) > RUBBLE_PUSH_TOLERANCE);
    // The group's largest changes (float bits of values >= 0) of the sweep and the push sweep.
    __local uint largest[2];
    groupClear(largest, 2u);
    float residual = 0.0f, pushResidual = 0.0f;
    const uint begin = elementsBegin(count, mode, blockStarts);
    if (mode != RUBBLE_PGS_BLOCKS) {
        // A color: each element's normal rows, then its friction rows, then its push rows.
        for (uint i = begin; i < end; ++i) {
            const PgsElement e = elements[first + i];
            residual = fmax(residual, solveElement(e, normalRows, frictionRows, impulses, joints,
                                                   jointRows, bodies, velocities, relaxation,
                                                   lastSweep, kept, RUBBLE_PGS_NORMALS |
                                                   RUBBLE_PGS_FRICTION, RUBBLE_PGS_ALL_SLOTS,
                                                   sweep & 1u));
            if (pushes)
                pushResidual = fmax(pushResidual, pushElement(e, normalRows, impulses, pushed,
                                                              push, relaxation,
                                                              RUBBLE_PGS_ALL_SLOTS));
        }
    } else {
        // A block, in order: the normal rows as the CPU's sweep goes through them (slotPasses),
        // then the friction rows by point too (byPoint: the CPU's order, which leaves debris_64k's
        // edge columns standing as on the CPU; docs/opencl.md). The push rows go in the CPU's
        // order too, each pass beside the normal rows' pass of the same point, which has just
        // read the row: the split pass reads and writes only its own velocities and its impulses'
        // w, so neither pass sees the other and each gives the same bits as after the whole
        // velocity sweep, with the rows read once.
        const uint passes = slotPasses(mode, blockStarts);
        for (uint pass = 0u; pass < passes; ++pass)
            for (uint i = begin; i < end; ++i) {
                const PgsElement e = elements[first + i];
                residual = fmax(residual, solveElement(e, normalRows, frictionRows, impulses,
                                                       joints, jointRows, bodies, velocities,
                                                       relaxation, lastSweep, kept,
                                                       RUBBLE_PGS_NORMALS, passSlot(mode, pass),
                                                       0u));
                if (pushes)
                    pushResidual = fmax(pushResidual,
                                        pushElement(e, normalRows, impulses, pushed, push,
                                                    relaxation, passSlot(mode, pass)));
            }
        const uint frictionPasses = byPoint(mode) ? passes : 1u;
        for (uint pass = 0u; pass < frictionPasses; ++pass)
            for (uint i = begin; i < end; ++i)
                residual = fmax(residual,
                                solveElement(elements[first + i], normalRows, frictionRows,
                                             impulses, joints, jointRows, bodies, velocities,
                                             relaxation, lastSweep, kept, RUBBLE_PGS_FRICTION,
                                             byPoint(mode) ? pass : RUBBLE_PGS_ALL_SLOTS,
                                             0u));
    }
    if (lastSweep && residual > 0.0f) atomic_max(&largest[0], as_uint(residual));
    if (pushResidual > 0.0f) atomic_max(&largest[1], as_uint(pushResidual));
    if (!groupDone()) return;
    if (largest[0] > 0u) atomic_max(&status[RUBBLE_STATUS_RESIDUAL], largest[0]);
    if (largest[1] > 0u) atomic_max(&sweepResidual[pushSweep], largest[1]);
}

// When a row may bounce (the non-fused path: the push sweeps run after the velocity sweeps), one
// work-item per element after the velocity sweeps: each row that bounces (pgsBouncesItem, from
// its accumulated normal impulse) aims the split pass at pgsPushTargetItem, written over its
// push speed, and when that is above zero marks its moving bodies as pushed and the status block
// (so that applyPushes moves them), as solvePushes marks its rows' bodies.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
markBounces(const uint count, __global const PgsElement* elements,
            __global PgsNormalRow* normalRows, __global const float4* impulses,
            __global uint* pushed, __global uint* status) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const PgsElement e = elements[i];
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) return;
    int lifts = 0;
    for (uint k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k) {
        const PgsNormalRow r = normalRows[e.normal[k]];
        const float impulse = impulses[e.normal[k]].x;
        if (!pgsBouncesItem(r, impulse)) continue;
        const float target = pgsPushTargetItem(r, impulse);
        normalRows[e.normal[k]].speeds.y = target;
        lifts |= target > 0.0f;
    }
    if (!lifts) return;
    if (e.rows & RUBBLE_PGS_MOVES_A) atomic_or(&pushed[e.a], 1u);
    if (e.rows & RUBBLE_PGS_MOVES_B) atomic_or(&pushed[e.b], 1u);
    atomic_or(&status[RUBBLE_STATUS_PUSHED], 1u);
}

// One sweep of the split position pass alone, one launch (a color, the serial tail or the
// blocks): the non-fused
// path, after the velocity sweeps (and markBounces). A sweep after one whose largest change was
// within RUBBLE_PUSH_TOLERANCE does nothing.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
pushPgs(const uint first, const uint count, const uint mode,
        __global const PgsElement* elements, __global const uint* blockStarts,
        __global const PgsNormalRow* normalRows,
        __global float4* impulses, __global const uint* pushed, __global BodyVelocity* push,
        const float relaxation, const uint sweep, __global uint* sweepResidual) {
    if (sweep > 0u && !(as_float(sweepResidual[sweep - 1u]) > RUBBLE_PUSH_TOLERANCE)) return;
    __local uint largest;
    groupClear(&largest, 1u);
    const uint begin = elementsBegin(count, mode, blockStarts);
    const uint end = elementsEnd(count, mode, blockStarts);
    float residual = 0.0f;
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = begin; i < end; ++i)
            residual = fmax(residual, pushElement(elements[first + i], normalRows, impulses,
                                                  pushed, push, relaxation, passSlot(mode, pass)));
    if (residual > 0.0f) atomic_max(&largest, as_uint(residual));
    if (groupDone() && largest > 0u) atomic_max(&sweepResidual[sweep], largest);
}

// One sweep of the restitution pass for one element, or for one of its points (`slot`): each of
// its rows that bounces, on the velocities. Returns the largest |change|, N s.
static float bounceElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                           __global const float4* impulses, __global float* bounce,
                           __global BodyVelocity* velocities, const uint sweep, const uint slot) {
    const uint from = slotFrom(slot), to = slotEnd(e.rows & RUBBLE_PGS_POINTS, slot);
    if ((e.id & RUBBLE_PGS_JOINT_ELEMENT) || from >= to) return 0.0f;
    BodyVelocityPair v = loadPair(e.a, e.b, velocities);
    float residual = 0.0f;
    int changed = 0;
    for (uint k = from; k < to; ++k) {
        const PgsNormalRow r = normalRows[e.normal[k]];
        const float impulse = impulses[e.normal[k]].x;
        if (!pgsBouncesItem(r, impulse)) continue;
        const float start = sweep == 0u ? 0.0f : bounce[e.normal[k]];
        const PgsUpdate u = solvePgsBounceItem(r, v, start, impulse);
        v = u.v;
        bounce[e.normal[k]] = u.accumulated;
        residual = fmax(residual, fabs(u.applied));
        changed = 1;
    }
    if (changed) storePair(v, e.a, e.b, e.rows, velocities);
    return residual;
}

// One sweep of the restitution pass, one launch (as the sweeps), after integratePositions
// (solveRestitution): each row that bounces gives its bodies back its bounce speed along the
// normal (solvePgsBounceItem) on the velocities the sweeps left (a copy: integratePositions has
// derived the bodies' own again at their new orientations), its impulse accumulated in `bounce`
// (from zero at sweep 0). A sweep after one whose largest change was within RUBBLE_PUSH_TOLERANCE does
// nothing.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
bouncePgs(const uint first, const uint count, const uint mode,
          __global const PgsElement* elements, __global const uint* blockStarts,
          __global const PgsNormalRow* normalRows,
          __global const float4* impulses, __global float* bounce,
          __global BodyVelocity* velocities, const uint sweep, __global uint* sweepResidual) {
    if (sweep > 0u && !(as_float(sweepResidual[sweep - 1u]) > RUBBLE_PUSH_TOLERANCE)) return;
    __local uint largest;
    groupClear(&largest, 1u);
    const uint begin = elementsBegin(count, mode, blockStarts);
    const uint end = elementsEnd(count, mode, blockStarts);
    float residual = 0.0f;
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = begin; i < end; ++i)
            residual = fmax(residual, bounceElement(elements[first + i], normalRows, impulses,
                                                    bounce, velocities, sweep,
                                                    passSlot(mode, pass)));
    if (residual > 0.0f) atomic_max(&largest, as_uint(residual));
    if (groupDone() && largest > 0u) atomic_max(&sweepResidual[sweep], largest);
}

// After the restitution pass's sweeps, one launch (as the sweeps): each bouncing row's
// impulse goes into its moving bodies' momenta (P += lambda_b n, L += lambda_b (r x n) on b, the
// opposite on a: addBounceImpulses), and those bodies' velocities follow from their momenta at
// their orientations (PgsSolver::solvePositions).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
bounceMomenta(const uint first, const uint count, const uint mode,
              __global const PgsElement* elements, __global const uint* blockStarts,
              __global const PgsNormalRow* normalRows,
              __global const float4* impulses, __global const float* bounce,
              __global BodyMomentum* momenta, __global const BodyMass* masses,
              __global const BodyPose* poses, __global BodyVelocity* velocities) {
    const uint end = elementsEnd(count, mode, blockStarts);
    for (uint i = elementsBegin(count, mode, blockStarts); i < end; ++i) {
        const PgsElement e = elements[first + i];
        if (e.id & RUBBLE_PGS_JOINT_ELEMENT) continue;
        int bounced = 0;
        for (uint k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k) {
            const PgsNormalRow r = normalRows[e.normal[k]];
            if (!pgsBouncesItem(r, impulses[e.normal[k]].x)) continue;
            const float l = bounce[e.normal[k]];
            const float4 linear = scale4(r.normal, l);
            if (r.speeds.z > 0.0f) {
                momenta[e.a].linear = sub4(momenta[e.a].linear, linear);
                momenta[e.a].angular = sub4(momenta[e.a].angular, scale4(r.crossA, l));
            }
            if (r.speeds.w > 0.0f) {
                momenta[e.b].linear = add4(momenta[e.b].linear, linear);
                momenta[e.b].angular = add4(momenta[e.b].angular, scale4(r.crossB, l));
            }
            bounced = 1;
        }
        if (!bounced) continue;
        if (e.rows & RUBBLE_PGS_MOVES_A)
            velocities[e.a] =
                velocityFromMomentumItem(momenta[e.a], masses[e.a], poses[e.a].orientation);
        if (e.rows & RUBBLE_PGS_MOVES_B)
            velocities[e.b] =
                velocityFromMomentumItem(momenta[e.b], masses[e.b], poses[e.b].orientation);
    }
}

// What the layer pass marks on a body: it carries a heavy load, or it is in a joint.
#define RUBBLE_LAYER_LOADED 1u
#define RUBBLE_LAYER_JOINED 2u

// The row `entry` of the layer pass's lists names: element index << 2 | point.
static uint layerRow(const uint entry, __global const PgsElement* elements) {
    return elements[entry >> 2].normal[entry & 3u];
}

// The layer pass (shock propagation; PgsSolver's solveLayers, then its rows on the split pass's
// velocities as solvePushes ends), after the sweeps of a step whose summaries found moving bodies
// RUBBLE_LAYER_MASS_RATIO times apart in mass. It walks every row and body in order, so it runs
// on one work-item: each body's layer (0 for a body that does not move, else one more than the
// lowest it touches through a row), the rows between layers whose upper body is that much
// heavier than the lower one or carries such a load (top down, a stable counting sort by the
// lower layer), then once more from the bottom up, each row moving its upper body only
// (solvePgsNormalOntoItem): on the velocities toward the row's target, and, when the split pass
// ran (`pushes`, and some row pushed), on the push velocities toward its push target for the
// rows that push or touch a pushed body. Rows of jointed bodies take no part. Scratch: layer and
// loaded per body, lists and the histogram of lower layers (bodies + 1 words).
__kernel void layerPgs(const uint count, __global const PgsElement* elements,
                       __global const PgsNormalRow* normalRows, __global const float4* impulses,
                       __global const JacobiBody* bodies, const uint bodyCount,
                       __global const PgsJoint* joints, const uint jointCount,
                       __global BodyVelocity* velocities, const uint pushes,
                       __global const uint* pushed, __global BodyVelocity* push,
                       __global const uint* status, __global uint* layer, __global uint* loaded,
                       __global uint* rows, __global uint* sorted, __global uint* histogram) {
    if (get_global_id(0) != 0u) return;
    for (uint i = 0; i < bodyCount; ++i) loaded[i] = 0u;
    for (uint j = 0; j < jointCount; ++j)
        loaded[joints[j].a] = loaded[joints[j].b] = RUBBLE_LAYER_JOINED;
    // Most steps have no such pair outside the joints: nothing to do.
    int any = 0;
    for (uint i = 0; i < count && !any; ++i) {
        const PgsElement e = elements[i];
        if (e.id & RUBBLE_PGS_JOINT_ELEMENT || loaded[e.a] || loaded[e.b]) continue;
        for (uint k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k) {
            const PgsNormalRow r = normalRows[e.normal[k]];
            any = any || heavyOverItem(r.speeds.z, r.speeds.w) ||
                  heavyOverItem(r.speeds.w, r.speeds.z);
        }
    }
    if (!any) return;
    // Layers up from the bodies that do not move, until no row lowers one.
    for (uint i = 0; i < bodyCount; ++i)
        layer[i] = jointInverseMassItem(bodies[i]) > 0.0f ? RUBBLE_NO_LAYER : 0u;
    for (int changed = 1; changed;) {
        changed = 0;
        for (uint i = 0; i < count; ++i) {
            const PgsElement e = elements[i];
            if (e.id & RUBBLE_PGS_JOINT_ELEMENT || (e.rows & RUBBLE_PGS_POINTS) == 0u) continue;
            if (layer[e.a] != RUBBLE_NO_LAYER && layer[e.a] + 1u < layer[e.b]) {
                layer[e.b] = layer[e.a] + 1u;
                changed = 1;
            }
            if (layer[e.b] != RUBBLE_NO_LAYER && layer[e.b] + 1u < layer[e.a]) {
                layer[e.a] = layer[e.b] + 1u;
                changed = 1;
            }
        }
    }
    // The rows between two layers, outside the joints, by lower layer from the top down.
    uint n = 0, top = 0;
    for (uint i = 0; i < count; ++i) {
        const PgsElement e = elements[i];
        if (e.id & RUBBLE_PGS_JOINT_ELEMENT) continue;
        const uint la = layer[e.a], lb = layer[e.b];
        if (la == lb || la == RUBBLE_NO_LAYER || lb == RUBBLE_NO_LAYER ||
            loaded[e.a] == RUBBLE_LAYER_JOINED || loaded[e.b] == RUBBLE_LAYER_JOINED)
            continue;
        for (uint k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k) rows[n++] = i << 2 | k;
        top = max(top, min(la, lb));
    }
    for (uint l = 0; l <= top; ++l) histogram[l] = 0u;
    for (uint i = 0; i < n; ++i) {
        const PgsElement e = elements[rows[i] >> 2];
        ++histogram[min(layer[e.a], layer[e.b])];
    }
    // Starts, highest layer first; then placed in order (stable).
    uint start = 0;
    for (uint l = top + 1u; l-- > 0u;) {
        const uint c = histogram[l];
        histogram[l] = start;
        start += c;
    }
    for (uint i = 0; i < n; ++i) {
        const PgsElement e = elements[rows[i] >> 2];
        sorted[histogram[min(layer[e.a], layer[e.b])]++] = rows[i];
    }
    // Top down: a row takes part when its upper body is that much heavier than its lower one,
    // or carries such a load; its lower body then carries it.
    uint kept = 0;
    for (uint i = 0; i < n; ++i) {
        const uint entry = sorted[i];
        const PgsElement e = elements[entry >> 2];
        const PgsNormalRow r = normalRows[layerRow(entry, elements)];
        const int upperIsB = layer[e.b] > layer[e.a];
        const uint up = upperIsB ? e.b : e.a, down = upperIsB ? e.a : e.b;
        const float upInverse = upperIsB ? r.speeds.w : r.speeds.z;
        const float downInverse = upperIsB ? r.speeds.z : r.speeds.w;
        if (!heavyOverItem(upInverse, downInverse) && loaded[up] != RUBBLE_LAYER_LOADED) continue;
        loaded[down] = RUBBLE_LAYER_LOADED;
        rows[kept++] = entry;
    }
    // Bottom up, each row stopping its upper body against the lower one.
    const int pushPass = pushes && status[RUBBLE_STATUS_PUSHED];
    for (uint i = kept; i-- > 0u;) {
        const uint entry = rows[i];
        const PgsElement e = elements[entry >> 2];
        const uint row = layerRow(entry, elements);
        const PgsNormalRow r = normalRows[row];
        const float4 l = impulses[row];
        const int upperIsB = layer[e.b] > layer[e.a];
        BodyVelocityPair v = loadPair(e.a, e.b, velocities);
        PgsUpdate u = solvePgsNormalOntoItem(r, v, upperIsB, r.speeds.x, l.x);
        if (upperIsB) velocities[e.b] = u.v.b;
        else velocities[e.a] = u.v.a;
        if (!pushPass || (r.speeds.y <= 0.0f && !pushed[e.a] && !pushed[e.b])) continue;
        v = loadPair(e.a, e.b, push);
        u = solvePgsNormalOntoItem(r, v, upperIsB, r.speeds.y, l.w);
        if (upperIsB) push[e.b] = u.v.b;
        else push[e.a] = u.v.a;
    }
}

// After integratePositions, when some row pushed: every body that moved in the solve is moved
// by dt times its push velocity, and its velocities follow from its momenta at the new
// orientation (PgsSolver::solvePositions).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
applyPushes(const uint count, __global const uint* status, __global const JacobiBody* bodies,
            __global const BodyVelocity* push, __global const BodyMomentum* momenta,
            __global const BodyMass* masses, __global BodyPose* poses,
            __global BodyVelocity* velocities, const float dt) {
    const uint i = get_global_id(0);
    if (i >= count || !status[RUBBLE_STATUS_PUSHED]) return;
    if (!movesInSolveItem(bodies[i])) return;
    const BodyVelocity v = push[i];
    BodyPose pose = poses[i];
    pose.position = add4(pose.position, scale4(v.linear, dt));
    pose.orientation = quatIntegrate(pose.orientation, v.angular, dt);
    poses[i] = pose;
    velocities[i] = velocityFromMomentumItem(momenta[i], masses[i], pose.orientation);
}

// Stage buildContactRows for joints (prepareJoints): one work-item per joint.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
prepareJoints(const uint count, __global const PgsJoint* joints, __global const BodyPose* poses,
              __global const JacobiBody* bodies, const uint warmStart, const float dt,
              __global PgsJointRow* jointRows) {
    const uint j = get_global_id(0);
    if (j >= count) return;
    const PgsJoint joint = joints[j];
    jointRows[j] = prepareJointItem(joint, jointRows[j], poses[joint.a], poses[joint.b],
                                    bodies[joint.a], bodies[joint.b], (int)warmStart, dt);
}

// The joints' position projection of the groups solved as one (the CPU path's direct
// correction), one work-item per group: projectJointGroupItem on the group's scratch.
__kernel void projectJointGroups(const uint count, __global const JointGroup* groups,
                                 __global const uint* members, __global const PgsJoint* joints,
                                 __global const BodyMass* masses, __global const uint* flags,
                                 __global BodyPose* poses, __global JointPositionRow* rows,
                                 __global JointReal* matrix, __global JointReal* solution,
                                 __global float4* deltaPosition, __global float4* deltaRotation,
                                 const int iterations) {
    const uint g = get_global_id(0);
    if (g >= count) return;
    const JointGroup group = groups[g];
    projectJointGroupItem(members + group.first, group.count, joints, masses, flags, poses,
                          rows + group.rowStart, matrix + group.matrixStart,
                          solution + group.rowStart, deltaPosition, deltaRotation, iterations);
}

// One sweep of the joints' position projection, one color of joints (no two share a dynamic
// body): each joint one Newton step onto its constraints (projectJointItem). A sweep after one
// that moved nothing does nothing: every joint holds.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
projectJoints(const uint first, const uint count, __global const uint* order,
              __global const PgsJoint* joints, __global const BodyMass* masses,
              __global const uint* flags, __global BodyPose* poses, const uint sweep,
              __global uint* sweepMoved) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    if (sweep > 0u && sweepMoved[sweep - 1u] == 0u) return;
    const PgsJoint joint = joints[order[first + i]];
    const BodyPose pa = poses[joint.a], pb = poses[joint.b];
    int moved = 0;
    const PosePair out =
        projectJointItem(joint, pa, pb, projectionBodyItem(masses[joint.a], flags[joint.a], pa),
                         projectionBodyItem(masses[joint.b], flags[joint.b], pb), &moved);
    if (!moved) return;
    poses[joint.a] = out.a;
    poses[joint.b] = out.b;
    sweepMoved[sweep] = 1u;
}

// After the projection: the jointed bodies' angular velocities follow from their momenta at
// the new orientations (PgsSolver::solvePositions). One work-item per jointed body.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
jointVelocities(const uint count, __global const uint* jointBodies,
                __global const BodyMass* masses, __global const uint* flags,
                __global const BodyPose* poses, __global const BodyMomentum* momenta,
                __global BodyVelocity* velocities) {
    const uint k = get_global_id(0);
    if (k >= count) return;
    const uint i = jointBodies[k];
    const BodyMass m = masses[i];
    if (!activeBodyItem(flags[i]) || !(m.inverseMass > 0.0f)) return;
    velocities[i] = velocityFromMomentumItem(momenta[i], m, poses[i].orientation);
}
