// kernels/pgs_bounce.cl: entry points of the restitution pass of projected Gauss-Seidel on the
// device, after integratePositions: its sweeps (bouncePgs) and its impulses into the momenta
// (bounceMomenta). The CPU twin is PgsSolver's solveRestitution (host/dynamics/pgs_solver.cpp).
#include "rubble/shared/pgs_element.h"

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
// (from zero at sweep 0). A sweep after one whose largest change was within
// RUBBLE_PUSH_TOLERANCE does nothing.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
bouncePgs(const uint first, const uint count, const uint mode,
          __global const PgsElement* elements, __global const uint* blockStarts,
          __global const PgsNormalRow* normalRows,
          __global const float4* impulses, __global float* bounce,
          __global BodyVelocity* velocities, const uint sweep, __global uint* sweepResidual) {
    if (sweep > 0u && !(as_float(sweepResidual[sweep - 1u]) > RUBBLE_PUSH_TOLERANCE)) return;
    __local uint largest;
    groupClear(&largest, 1u);
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    float residual = 0.0f;
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = range.begin; i < range.end; i += range.step)
            residual = fmax(residual, bounceElement(elements[range.first + i], normalRows, impulses,
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
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    for (uint i = range.begin; i < range.end; i += range.step) {
        const PgsElement e = elements[range.first + i];
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
