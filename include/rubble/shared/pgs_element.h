// include/rubble/shared/pgs_element.h: one element of the device's projected Gauss-Seidel
// launches (kernels/pgs_sweep.cl, pgs_push.cl, pgs_bounce.cl): which elements a work-item of a
// launch takes (its mode), which points a pass over an element takes (its slot), the element's
// two velocities, and the split position pass's sweep of one element, which both the fused
// velocity sweep and the pass's own launch run. Device only: the host's twin is PgsSolver.
#pragma once

#include "rubble/shared/group.h"
#include "rubble/shared/pgs_coloring.h"
#include "rubble/shared/pgs_joint.h"

#ifdef __OPENCL_C_VERSION__

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

// A launch's elements: elements[first + i] for i from begin below end, step apart. A device
// plan's launch (RUBBLE_PGS_COLOR, RUBBLE_PGS_OVERFLOW) takes its range from the color starts,
// `first` being the color, whatever the launch's size.
typedef struct ElementRange {
    uint first, begin, end, step;
} ElementRange;
static ElementRange elementRange(const uint first, const uint count, const uint mode,
                                 __global const uint* blockStarts) {
    ElementRange r;
    r.step = 1u;
    if (mode == RUBBLE_PGS_COLOR || mode == RUBBLE_PGS_OVERFLOW) {
        r.first = blockStarts[first];
        const uint n = blockStarts[first + 1u] - r.first;
        const int each = mode == RUBBLE_PGS_COLOR;
        r.begin = each ? (uint)get_global_id(0) : 0u;
        r.end = each || get_global_id(0) == 0u ? n : 0u;
        r.step = each ? (uint)get_global_size(0) : 1u;
        return r;
    }
    r.first = first;
    r.begin = elementsBegin(count, mode, blockStarts);
    r.end = elementsEnd(count, mode, blockStarts);
    return r;
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

// The per-element solves (solveElement, pushElement) are called from several places (a color's
// loop, a block's passes, the friction passes, pushPgs). PoCL's compiler leaves them calls;
// forced inline, each place gets a copy specialised to its constant `part`, `slot` and
// `backward`, without the branches it never takes, at the price of a longer first build.
#define RUBBLE_PGS_INLINE static inline __attribute__((always_inline))

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

#endif
