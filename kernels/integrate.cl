// kernels/integrate.cl: entry points of OpenCL stages 1 and 6 (integrateVelocities,
// integratePositions) and the momentum update after the solve; the math is in
// rubble/shared/body.h, the CPU twins in host/core/integrate.cpp.
#include "rubble/shared/body.h"
#include "rubble/shared/contact_row.h"

// Kinematic bodies keep the velocity the host gave them; sleeping ones keep their state unless
// the host put a force on them, which wakes them. Every body's velocities before the forces go
// to atStart: restitution's approach speeds, explicit Euler's motion.
__kernel void integrateVelocities(const uint count, __global BodyMomentum* momenta,
                                  __global const BodyForce* forces,
                                  __global const BodyMass* masses, __global uint* flags,
                                  __global const BodyPose* poses,
                                  __global BodyVelocity* velocities,
                                  __global BodyVelocity* atStart, const float4 gravity,
                                  const float dt) {
    const uint i = get_global_id(0);
    if (i >= count) return; // the global size is rounded up to the group size
    const uint f = flags[i];
    if (f & RUBBLE_BODY_KINEMATIC) {
        atStart[i] = velocities[i];
        return;
    }
    atStart[i] = beforeForcesItem(momenta[i], masses[i], velocities[i]);
    const BodyForce force = forces[i];
    if (f & RUBBLE_BODY_ASLEEP) {
        if (dot3(force.force, force.force) == 0.0f && dot3(force.torque, force.torque) == 0.0f)
            return;
        flags[i] = f & ~RUBBLE_BODY_ASLEEP;
    }
    const BodyMass m = masses[i];
    const BodyMomentum p = integrateMomentumItem(momenta[i], force, m, gravity, dt);
    momenta[i] = p;
    velocities[i] = velocityFromMomentumItem(p, m, poses[i].orientation);
}

// Bodies whose velocity the solve did not change keep their momenta bit for bit.
__kernel void absorbVelocityChange(const uint count, __global BodyMomentum* momenta,
                                   __global const BodyVelocity* before,
                                   __global const BodyVelocity* after,
                                   __global const BodyMass* masses,
                                   __global const BodyPose* poses) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    momenta[i] = absorbVelocityChangeItem(momenta[i], before[i], after[i], masses[i],
                                          poses[i].orientation);
}

// status[RUBBLE_STATUS_NONFINITE] keeps the lowest index of a body whose pose is not finite.
// Nothing moves in a step whose contacts overflowed: the host runs its second half again. With
// `pushesFollow` (applyPushes is the next kernel, PGS's split position pass having pushed), a
// body that moved in the solve (`bodies`: its JacobiBody) gets its velocities from applyPushes,
// at its pushed orientation, and none here.
__kernel void integratePositions(const uint count, __global uint* status,
                                 __global const uint* flags, __global BodyPose* poses,
                                 __global BodyVelocity* velocities,
                                 __global const BodyVelocity* atStart,
                                 __global const BodyMomentum* momenta,
                                 __global const BodyMass* masses, const float dt,
                                 const uint symplectic, __global const JacobiBody* bodies,
                                 const uint pushesFollow) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    if (status[RUBBLE_STATUS_CONTACTS] > status[RUBBLE_STATUS_CAPACITY]) return;
    const BodyMass m = masses[i];
    // A kinematic body of the scene moves with its own velocities, which nothing changes (the
    // host's bodies of debris offloading are placed by the host instead).
    if (m.flags & RUBBLE_BODY_KINEMATIC) {
        const BodyPose pose = integratePositionItem(poses[i], velocities[i], dt);
        poses[i] = pose;
        const float4 x = pose.position, q = pose.orientation;
        if (!isfinite(x.x + x.y + x.z + q.x + q.y + q.z + q.w))
            atomic_min(&status[RUBBLE_STATUS_NONFINITE], i);
        return;
    }
    if (m.inverseMass == 0.0f || (flags[i] & RUBBLE_BODY_ASLEEP)) return;
    const BodyMomentum p = momenta[i];
    const BodyPose pose = symplectic
                              ? integratePositionSymplecticItem(poses[i], velocities[i], p, m, dt)
                              : integratePositionItem(poses[i], atStart[i], dt);
    poses[i] = pose;
    if (!pushesFollow || !movesInSolveItem(bodies[i]))
        velocities[i] = velocityFromMomentumItem(p, m, pose.orientation);
    const float4 x = pose.position, q = pose.orientation;
    if (!isfinite(x.x + x.y + x.z + q.x + q.y + q.z + q.w + p.linear.x + p.linear.y +
                  p.linear.z + p.angular.x + p.angular.y + p.angular.z))
        atomic_min(&status[RUBBLE_STATUS_NONFINITE], i);
}
