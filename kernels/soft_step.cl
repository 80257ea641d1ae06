// kernels/soft_step.cl: entry points of the soft step on the device (Catto's soft step over the
// PGS path's elements, rows, blocks and colors): the soft points, the substeps' forces, warm
// start, biased and relax passes and motion, restitution with the impulses kept, and the step's
// end. The math is in rubble/shared/soft_step.h; the CPU twin is SoftStepSolver
// (host/dynamics/soft_step.cpp).
#include "rubble/shared/narrow_phase.h"
#include "rubble/shared/pgs_element.h"
#include "rubble/shared/soft_step.h"

// One work-item per pair with rows, in pair order (as buildPgsRows): each manifold point's soft
// contact where its element places its rows.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
prepareSoftContacts(const uint count, __global const uint* order,
                    __global const PgsElement* elements, __global const ContactManifold* manifolds,
                    __global const BodyPose* poses, __global const BodyVelocity* approach,
                    __global const float4* surfaces, __global SoftContact* contacts) {
    const uint i = get_global_id(0);
    if (i >= count || order[i] == RUBBLE_PGS_NO_ELEMENT) return;
    const PgsElement e = elements[order[i]];
    const uint points = e.rows & RUBBLE_PGS_POINTS;
    const ContactManifold m = manifolds[e.id];
    const BodyPose pa = poses[e.a], pb = poses[e.b];
    const BodyVelocity aa = approach[e.a], ab = approach[e.b];
    const float restitution = fmax(surfaces[e.a].y, surfaces[e.b].y);
    for (uint k = 0; k < points; ++k)
        contacts[e.normal[k]] =
            softContactItem(m.points[k], m.points[k].w, m.normal, pa, pb, aa, ab, restitution);
}

// One work-item per body: a body that moves starts the substeps from its velocities before the
// step's forces and keeps 1/substeps of their change for each substep, the first substep's
// share added here (addSoftForces adds the others'); every body's pose is copied to the
// substeps' poses, and the motion within the step starts at zero.
__kernel void beginSoftStep(const uint count, __global const JacobiBody* bodies,
                            __global const BodyPose* poses, __global const BodyVelocity* atStart,
                            __global BodyVelocity* velocities, __global BodyVelocity* share,
                            __global BodyPose* softPoses, __global float4* moved,
                            const float shareOfForces) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    softPoses[i] = poses[i];
    moved[i] = vec4(0.0f, 0.0f, 0.0f);
    if (!movesInSolveItem(bodies[i])) return;
    const BodyVelocity s = atStart[i], v = velocities[i];
    BodyVelocity start, d;
    start.linear = vec4(s.linear.x, s.linear.y, s.linear.z);
    start.angular = vec4(s.angular.x, s.angular.y, s.angular.z);
    d.linear = scale4(sub4(vec4(v.linear.x, v.linear.y, v.linear.z), start.linear), shareOfForces);
    d.angular =
        scale4(sub4(vec4(v.angular.x, v.angular.y, v.angular.z), start.angular), shareOfForces);
    share[i] = d;
    start.linear = add4(start.linear, d.linear);
    start.angular = add4(start.angular, d.angular);
    velocities[i] = start;
}

// One work-item per body, from the second substep on: a substep's share of the forces' velocity
// change.
__kernel void addSoftForces(const uint count, __global const JacobiBody* bodies,
                            __global const BodyVelocity* share, __global BodyVelocity* velocities) {
    const uint i = get_global_id(0);
    if (i >= count || !movesInSolveItem(bodies[i])) return;
    BodyVelocity v = velocities[i];
    const BodyVelocity s = share[i];
    v.linear = add4(v.linear, s.linear);
    v.angular = add4(v.angular, s.angular);
    velocities[i] = v;
}

// A joint's rows at the substep's poses, with its accumulated impulses.
static PgsJointRow softJointRow(const PgsElement e, __global const PgsJoint* joints,
                                __global const PgsJointRow* jointRows, const JacobiBody ja,
                                const JacobiBody jb, __global const BodyPose* softPoses) {
    const uint j = e.id & ~RUBBLE_PGS_JOINT_ELEMENT;
    return prepareJointItem(joints[j], jointRows[j], softPoses[e.a], softPoses[e.b], ja, jb, 1,
                            0.0f);
}

// Warm start of one element, or of one of its points (`slot`, as the PGS sweeps'): a joint's
// impulses at the substep's poses (with the first point), a pair's points' normal and friction
// impulses (warmStartJoints, warmStartContacts).
static void warmStartSoftElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                                 __global const PgsFrictionRows* frictionRows,
                                 __global const float4* impulses, __global const PgsJoint* joints,
                                 __global const PgsJointRow* jointRows,
                                 __global const JacobiBody* bodies,
                                 __global const BodyPose* softPoses,
                                 __global BodyVelocity* velocities, const uint slot) {
    const uint from = slotFrom(slot), to = slotEnd(e.rows & RUBBLE_PGS_POINTS, slot);
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) {
        if (from > 0u) return;
        const JacobiBody ja = bodies[e.a], jb = bodies[e.b];
        const PgsJointRow r = softJointRow(e, joints, jointRows, ja, jb, softPoses);
        BodyVelocityPair v = loadPair(e.a, e.b, velocities);
        v = warmStartJointItem(v, joints[e.id & ~RUBBLE_PGS_JOINT_ELEMENT], r, ja, jb);
        storePair(v, e.a, e.b, jointMoves(ja, jb), velocities);
        return;
    }
    if (from >= to) return;
    BodyVelocityPair v = loadPair(e.a, e.b, velocities);
    for (uint k = from; k < to; ++k) {
        const float4 l = impulses[e.normal[k]];
        const PgsNormalRow r = normalRows[e.normal[k]];
        v = applyPgsRowItem(v, r.normal, r.turnA, r.turnB, r.speeds.z, r.speeds.w, l.x);
        const PgsFrictionRows f = frictionRows[e.normal[k]];
        const float ima = f.inverseMass.x, imb = f.inverseMass.y;
        v = applyPgsRowItem(v, f.tangent[0], f.turnA[0], f.turnB[0], ima, imb, l.y);
        v = applyPgsRowItem(v, f.tangent[1], f.turnA[1], f.turnB[1], ima, imb, l.z);
    }
    storePair(v, e.a, e.b, e.rows, velocities);
}

// A substep's warm start, one launch (a color, the serial tail or the blocks by point).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
warmStartSoft(const uint first, const uint count, const uint mode,
              __global const PgsElement* elements, __global const uint* blockStarts,
              __global const PgsNormalRow* normalRows, __global const PgsFrictionRows* frictionRows,
              __global const float4* impulses, __global const PgsJoint* joints,
              __global const PgsJointRow* jointRows, __global const JacobiBody* bodies,
              __global const BodyPose* softPoses, __global BodyVelocity* velocities) {
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = range.begin; i < range.end; i += range.step)
            warmStartSoftElement(elements[range.first + i], normalRows, frictionRows, impulses,
                                 joints, jointRows, bodies, softPoses, velocities,
                                 passSlot(mode, pass));
}

// One pass over one element, or one of its points (`slot`): a joint's soft blocks at the
// substep's poses (with the first point), a pair's points each its normal row at the separation
// now, then its friction rows (solveJoints, solveContacts); impulses.w keeps each point's largest
// normal impulse for restitution. Returns the largest |change|, N s.
static float solveSoftElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                              __global const PgsFrictionRows* frictionRows,
                              __global float4* impulses, __global const SoftContact* contacts,
                              __global const PgsJoint* joints, __global PgsJointRow* jointRows,
                              __global const JacobiBody* bodies, __global const BodyPose* softPoses,
                              __global const float4* moved, __global BodyVelocity* velocities,
                              const SoftPass p, const float4 jointSoft, const uint slot) {
    const uint from = slotFrom(slot), to = slotEnd(e.rows & RUBBLE_PGS_POINTS, slot);
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) {
        if (from > 0u) return 0.0f;
        const uint j = e.id & ~RUBBLE_PGS_JOINT_ELEMENT;
        const JacobiBody ja = bodies[e.a], jb = bodies[e.b];
        const BodyPose pa = softPoses[e.a], pb = softPoses[e.b];
        const PgsJointRow r = softJointRow(e, joints, jointRows, ja, jb, softPoses);
        const float4 soft = p.useBias ? jointSoft : make4(0.0f, 1.0f, 0.0f, 0.0f);
        const PgsJointUpdate u =
            solveSoftJointItem(loadPair(e.a, e.b, velocities), joints[j], r, pa, pb, ja, jb, soft);
        storePair(u.v, e.a, e.b, jointMoves(ja, jb), velocities);
        jointRows[j].pointImpulse = vec4(u.pointImpulse.x, u.pointImpulse.y, u.pointImpulse.z);
        jointRows[j].turnImpulse = u.turnImpulse;
        return u.pointImpulse.w;
    }
    if (from >= to) return 0.0f;
    BodyVelocityPair v = loadPair(e.a, e.b, velocities);
    const BodyPose pa = softPoses[e.a], pb = softPoses[e.b];
    const float4 movedA = moved[e.a], movedB = moved[e.b];
    float residual = 0.0f;
    for (uint k = from; k < to; ++k) {
        const uint at = e.normal[k];
        float4 l = impulses[at];
        const PgsNormalRow r = normalRows[at];
        const float separation = softSeparationItem(contacts[at], r.normal, movedA, pa.orientation,
                                                    movedB, pb.orientation);
        const PgsUpdate n = solveSoftNormalItem(r, v, softPointItem(r, separation, p), l.x);
        v = n.v;
        l.x = n.accumulated;
        l.w = l.w < l.x ? l.x : l.w; // std::max(largest, total)
        residual = fmax(residual, fabs(n.applied));
        const PgsFrictionUpdate f = solveSoftFrictionItem(frictionRows[at], v, l.x, l.y, l.z);
        v = f.v;
        l.y = f.impulse.x;
        l.z = f.impulse.y;
        residual = fmax(residual, f.impulse.z);
        impulses[at] = l;
    }
    storePair(v, e.a, e.b, e.rows, velocities);
    return residual;
}

// A landing's normal rows together, along the direction that adds the same impulse to every
// point (solveManifoldNormals): the exact minimum along it of what the point updates minimise,
// kept where no point's impulse goes below 0. A pair lands when one of its points was a gap at
// the step's start and approached faster than `threshold` (m/s) (isLanding). Returns the
// |change| per point, N s.
static float solveSoftManifold(const PgsElement e, __global const PgsNormalRow* normalRows,
                               __global float4* impulses, __global const SoftContact* contacts,
                               __global const BodyPose* softPoses, __global const float4* moved,
                               __global BodyVelocity* velocities, const SoftPass p,
                               const float threshold) {
    const uint points = e.rows & RUBBLE_PGS_POINTS;
    if ((e.id & RUBBLE_PGS_JOINT_ELEMENT) || points < 2u) return 0.0f;
    int landing = 0;
    for (uint k = 0; k < points; ++k) {
        const SoftContact c = contacts[e.normal[k]];
        landing |= c.anchorA.w > 0.0f && c.anchorB.w < -threshold;
    }
    if (!landing) return 0.0f;
    BodyVelocityPair v = loadPair(e.a, e.b, velocities);
    const BodyPose pa = softPoses[e.a], pb = softPoses[e.b];
    const float4 movedA = moved[e.a], movedB = moved[e.b];
    const PgsNormalRow first = normalRows[e.normal[0]];
    float slope = 0.0f, diagonal = 0.0f, lowest = impulses[e.normal[0]].x;
    float4 crossA = vec4(0.0f, 0.0f, 0.0f), turnA = crossA, crossB = crossA, turnB = crossA;
    for (uint k = 0; k < points; ++k) {
        const uint at = e.normal[k];
        const PgsNormalRow r = normalRows[at];
        const float impulse = impulses[at].x;
        const float separation = softSeparationItem(contacts[at], r.normal, movedA, pa.orientation,
                                                    movedB, pb.orientation);
        const float4 term = softManifoldTermItem(r, v, softPointItem(r, separation, p), impulse);
        slope += term.x;
        diagonal += term.y;
        lowest = impulse < lowest ? impulse : lowest; // std::min(lowest, impulse)
        crossA = add4(crossA, r.crossA);
        turnA = add4(turnA, r.turnA);
        crossB = add4(crossB, r.crossB);
        turnB = add4(turnB, r.turnB);
    }
    const float n = (float)points;
    const float curvature = n * n * (first.speeds.z + first.speeds.w) + dot3(crossA, turnA) +
                            dot3(crossB, turnB) + diagonal;
    if (!(curvature > 0.0f)) return 0.0f;
    const float step = -slope / curvature;
    const float change = step < -lowest ? -lowest : step; // std::max(step, -lowest)
    for (uint k = 0; k < points; ++k) {
        float4 l = impulses[e.normal[k]];
        l.x = l.x + change;
        l.w = l.w < l.x ? l.x : l.w; // std::max(largest, total)
        impulses[e.normal[k]] = l;
    }
    const float total = n * change;
    v.a.linear = sub4(v.a.linear, scale4(first.normal, first.speeds.z * total));
    v.a.angular = sub4(v.a.angular, scale4(turnA, change));
    v.b.linear = add4(v.b.linear, scale4(first.normal, first.speeds.w * total));
    v.b.angular = add4(v.b.angular, scale4(turnB, change));
    storePair(v, e.a, e.b, e.rows, velocities);
    return fabs(change);
}

// A biased (useBias 1) or relax (0) pass, one launch: the landing pairs' normal rows together,
// then a color's elements whole, a block's by point in the CPU's order. settings: x 1/h (1/s),
// y the largest push-out speed, z the restitution threshold (m/s). The last pass of the step
// puts its largest change in the status block.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
solveSoft(const uint first, const uint count, const uint mode, __global const PgsElement* elements,
          __global const uint* blockStarts, __global const PgsNormalRow* normalRows,
          __global const PgsFrictionRows* frictionRows, __global float4* impulses,
          __global const SoftContact* contacts, __global const PgsJoint* joints,
          __global PgsJointRow* jointRows, __global const JacobiBody* bodies,
          __global const BodyPose* softPoses, __global const float4* moved,
          __global BodyVelocity* velocities, const float4 soft, const float4 softStill,
          const float4 jointSoft, const float4 settings, const uint useBias, const uint lastPass,
          __global uint* status) {
    SoftPass p;
    p.soft = soft;
    p.softStill = softStill;
    p.inverseH = settings.x;
    p.maxPushSpeed = settings.y;
    p.useBias = (int)useBias;
    p.pad0 = 0;
    __local uint largest[1];
    groupClear(largest, 1u);
    float residual = 0.0f;
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    // Every landing's normal rows together first, then the joints and points, as the CPU.
    for (uint i = range.begin; i < range.end; i += range.step)
        residual = fmax(residual,
                        solveSoftManifold(elements[range.first + i], normalRows, impulses, contacts,
                                          softPoses, moved, velocities, p, settings.z));
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = range.begin; i < range.end; i += range.step)
            residual = fmax(
                residual, solveSoftElement(elements[range.first + i], normalRows, frictionRows,
                                           impulses, contacts, joints, jointRows, bodies, softPoses,
                                           moved, velocities, p, jointSoft, passSlot(mode, pass)));
    if (lastPass && residual > 0.0f) atomic_max(&largest[0], as_uint(residual));
    if (!groupDone()) return;
    if (largest[0] > 0u) atomic_max(&status[RUBBLE_STATUS_RESIDUAL], largest[0]);
}

// One work-item per body that moves: x += h v, q turned by h w (movePoses), and the motion
// within the step.
__kernel void integrateSoft(const uint count, __global const JacobiBody* bodies,
                            __global const BodyVelocity* velocities, const float h,
                            __global BodyPose* softPoses, __global float4* moved) {
    const uint i = get_global_id(0);
    if (i >= count || !movesInSolveItem(bodies[i])) return;
    const BodyVelocity v = velocities[i];
    const float4 step = scale4(vec4(v.linear.x, v.linear.y, v.linear.z), h);
    moved[i] = add4(moved[i], step);
    BodyPose pose = softPoses[i];
    pose.position = add4(vec4(pose.position.x, pose.position.y, pose.position.z), step);
    pose.orientation =
        quatIntegrate(pose.orientation, vec4(v.angular.x, v.angular.y, v.angular.z), h);
    softPoses[i] = pose;
}

// Restitution of one element, or of one of its points (`slot`), after the substeps
// (applyRestitution); then its points' impulses are kept for the next step's warm start, none
// for a landing (solveSoftStep).
static void bounceSoftElement(const PgsElement e, __global const PgsNormalRow* normalRows,
                              __global const PgsFrictionRows* frictionRows,
                              __global float4* impulses, __global const SoftContact* contacts,
                              __global BodyVelocity* velocities, const float threshold,
                              __global PgsImpulse* kept, __global const uint* impulseStart,
                              const uint slot) {
    const uint points = e.rows & RUBBLE_PGS_POINTS;
    const uint from = slotFrom(slot), to = slotEnd(points, slot);
    if ((e.id & RUBBLE_PGS_JOINT_ELEMENT) || from >= to) return;
    BodyVelocityPair v = loadPair(e.a, e.b, velocities);
    const uint start = impulseStart[e.id];
    // A landing's impulses stopped a hit, not a load: the next step starts its points cold.
    int landing = 0;
    for (uint k = 0; k < points; ++k) {
        const SoftContact c = contacts[e.normal[k]];
        landing |= c.anchorA.w > 0.0f && c.anchorB.w < -threshold;
    }
    for (uint k = from; k < to; ++k) {
        const uint at = e.normal[k];
        float4 l = impulses[at];
        const PgsUpdate u =
            softRestitutionItem(normalRows[at], contacts[at], v, l.x, l.w, threshold);
        v = u.v;
        l.x = u.accumulated;
        if (landing) l.x = l.y = l.z = 0.0f;
        impulses[at] = l;
        const PgsFrictionRows f = frictionRows[at];
        kept[start + k].normal = l.x;
        kept[start + k].friction = add4(scale4(f.tangent[0], l.y), scale4(f.tangent[1], l.z));
    }
    storePair(v, e.a, e.b, e.rows, velocities);
}

// Restitution and the impulses kept, one launch.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
bounceSoft(const uint first, const uint count, const uint mode, __global const PgsElement* elements,
           __global const uint* blockStarts, __global const PgsNormalRow* normalRows,
           __global const PgsFrictionRows* frictionRows, __global float4* impulses,
           __global const SoftContact* contacts, __global BodyVelocity* velocities,
           const float threshold, __global PgsImpulse* kept, __global const uint* impulseStart) {
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = range.begin; i < range.end; i += range.step)
            bounceSoftElement(elements[range.first + i], normalRows, frictionRows, impulses,
                              contacts, velocities, threshold, kept, impulseStart,
                              passSlot(mode, pass));
}

// One work-item per body, the step's end: the momenta take up the solve's velocity change at the
// step's start pose (absorbVelocityChange); a body that moved takes the substeps' pose and its
// velocities from its momenta there (SoftStepSolver::solvePositions). status keeps the lowest
// index of a body whose state is not finite.
__kernel void finishSoftStep(const uint count, __global uint* status,
                             __global const JacobiBody* bodies, __global const BodyMass* masses,
                             __global const BodyPose* softPoses,
                             __global const BodyVelocity* before, __global BodyVelocity* velocities,
                             __global BodyMomentum* momenta, __global BodyPose* poses) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const BodyMass m = masses[i];
    const BodyMomentum p =
        absorbVelocityChangeItem(momenta[i], before[i], velocities[i], m, poses[i].orientation);
    momenta[i] = p;
    if (!movesInSolveItem(bodies[i])) return;
    const BodyPose pose = softPoses[i];
    poses[i] = pose;
    velocities[i] = velocityFromMomentumItem(p, m, pose.orientation);
    const float4 x = pose.position, q = pose.orientation;
    if (!isfinite(x.x + x.y + x.z + q.x + q.y + q.z + q.w + p.linear.x + p.linear.y + p.linear.z +
                  p.angular.x + p.angular.y + p.angular.z))
        atomic_min(&status[RUBBLE_STATUS_NONFINITE], i);
}
