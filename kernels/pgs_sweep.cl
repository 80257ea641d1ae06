// kernels/pgs_sweep.cl: entry points of the device's projected Gauss-Seidel sweeps: the warm
// start (warmStartPgs) and the velocity sweeps (solvePgs), each launch one color, the serial tail
// or the blocks, with the split position pass's sweep beside each velocity sweep. The row math
// is in rubble/shared/pgs_row.h; the CPU twin is PgsSolver (host/dynamics/pgs_solver.cpp).
#include "rubble/shared/pgs_element.h"

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

// Warm start, one launch (a color, the serial tail or the blocks): a color's elements whole, a
// block's by point (slotPasses), the order in which the CPU's warmStartContacts goes through its
// interleaved rows.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
warmStartPgs(const uint first, const uint count, const uint mode,
             __global const PgsElement* elements, __global const uint* blockStarts,
             __global const PgsNormalRow* normalRows,
             __global const PgsFrictionRows* frictionRows, __global const float4* impulses,
             __global const PgsJoint* joints, __global const PgsJointRow* jointRows,
             __global const JacobiBody* bodies, __global BodyVelocity* velocities) {
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = range.begin; i < range.end; i += range.step)
            warmStartElement(elements[range.first + i], normalRows, frictionRows, impulses, joints,
                             jointRows, bodies, velocities, passSlot(mode, pass));
}

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
        kept[k].normal = l->x;
        kept[k].friction = add4(scale4(r.tangent[0], l->y), scale4(r.tangent[1], l->z));
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
// step until it sleeps or falls; alternating the order cancels that drift. A block's passes
// interleave the points of all its elements, as the CPU's sweep does, and need neither.
#define RUBBLE_PGS_ELEMENT_NORMAL_PASSES 2u
RUBBLE_PGS_INLINE float solveElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                                     __global const PgsFrictionRows* frictionRows,
                                     __global float4* impulses, __global const PgsJoint* joints,
                                     __global PgsJointRow* jointRows,
                                     __global const JacobiBody* bodies,
                                     __global BodyVelocity* velocities, const float relaxation,
                                     const uint lastSweep, __global PgsImpulse* kept,
                                     __global const uint* impulseStart,
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
    // The pair's kept impulses, which the last sweep writes (solvePoint).
    if (lastSweep) kept += impulseStart[e.id];
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
         __global PgsImpulse* kept, __global const uint* impulseStart, __global uint* status,
         const uint pushSweep,
         __global const uint* pushed,
         __global BodyVelocity* push, __global uint* sweepResidual) {
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    const int pushes = pushSweep != RUBBLE_PGS_NO_PUSH &&
                       (pushSweep == 0u ||
                        as_float(sweepResidual[pushSweep - 1u]) > RUBBLE_PUSH_TOLERANCE);
    // The group's largest changes (float bits of values >= 0) of the sweep and the push sweep.
    __local uint largest[2];
    groupClear(largest, 2u);
    float residual = 0.0f, pushResidual = 0.0f;
    const uint begin = range.begin, end = range.end;
    if (mode != RUBBLE_PGS_BLOCKS) {
        // A color: each element's normal rows, then its friction rows, then its push rows.
        for (uint i = begin; i < end; i += range.step) {
            const PgsElement e = elements[range.first + i];
            residual = fmax(residual, solveElement(e, normalRows, frictionRows, impulses, joints,
                                                   jointRows, bodies, velocities, relaxation,
                                                   lastSweep, kept, impulseStart,
                                                   RUBBLE_PGS_NORMALS | RUBBLE_PGS_FRICTION,
                                                   RUBBLE_PGS_ALL_SLOTS, sweep & 1u));
            if (pushes)
                pushResidual = fmax(pushResidual, pushElement(e, normalRows, impulses, pushed,
                                                              push, relaxation,
                                                              RUBBLE_PGS_ALL_SLOTS));
        }
    } else {
        // A block, in order: the normal rows as the CPU's sweep goes through them (slotPasses),
        // then the friction rows by point too, the CPU's order, so that a block steps the CPU's
        // bits when it holds every element between its bodies. The push rows go in the CPU's
        // order too, each pass beside the normal rows' pass of the same point, which has just
        // read the row: the split pass reads and writes only its own velocities and its impulses'
        // w, so neither pass sees the other and each gives the same bits as after the whole
        // velocity sweep, with the rows read once.
        const uint passes = slotPasses(mode, blockStarts);
        for (uint pass = 0u; pass < passes; ++pass)
            for (uint i = begin; i < end; ++i) {
                const PgsElement e = elements[range.first + i];
                residual = fmax(residual, solveElement(e, normalRows, frictionRows, impulses,
                                                       joints, jointRows, bodies, velocities,
                                                       relaxation, lastSweep, kept, impulseStart,
                                                       RUBBLE_PGS_NORMALS, pass, 0u));
                if (pushes)
                    pushResidual = fmax(pushResidual,
                                        pushElement(e, normalRows, impulses, pushed, push,
                                                    relaxation, pass));
            }
        for (uint pass = 0u; pass < passes; ++pass)
            for (uint i = begin; i < end; ++i)
                residual = fmax(residual,
                                solveElement(elements[range.first + i], normalRows, frictionRows,
                                             impulses, joints, jointRows, bodies, velocities,
                                             relaxation, lastSweep, kept, impulseStart,
                                             RUBBLE_PGS_FRICTION,
                                             pass, 0u));
    }
    if (lastSweep && residual > 0.0f) atomic_max(&largest[0], as_uint(residual));
    if (pushResidual > 0.0f) atomic_max(&largest[1], as_uint(pushResidual));
    if (!groupDone()) return;
    if (largest[0] > 0u) atomic_max(&status[RUBBLE_STATUS_RESIDUAL], largest[0]);
    if (largest[1] > 0u) atomic_max(&sweepResidual[pushSweep], largest[1]);
}
