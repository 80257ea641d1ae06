// kernels/integrate.cl: entry points of OpenCL stages 1 and 6 (integrateVelocities,
// integratePositions), the momentum update after the solve and the bodies' energy for the
// blow-up watch; the math is in
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

// The dynamic bodies' mechanical energy after the step, E = (v.P + w.L) / 2 - m g.x each, as
// host/dynamics/blowup_watch.cpp sums it for the blow-up watch: one group strides through the
// bodies (each work-item's sum compensated), its tree adds the work-items' sums, and the total
// and the sum of the terms' magnitudes (the scale of its rounding) go to the status block. When
// the total is below lowest[0] (or `restart`), it becomes lowest[0] and each body's energy goes
// to atLowest: the watch names the body that gained the most since.
__kernel void sumBodyEnergy(const uint count, __global uint* status,
                            __global const BodyPose* poses,
                            __global const BodyVelocity* velocities,
                            __global const BodyMomentum* momenta,
                            __global const BodyMass* masses, const float4 gravity,
                            const uint restart, __global float* energies,
                            __global float* atLowest, __global float* lowest) {
    __local float totals[RUBBLE_GROUP_BODIES];
    __local float scales[RUBBLE_GROUP_BODIES];
    __local uint lower;
    const uint lane = get_local_id(0);
    float sum = 0.0f, lost = 0.0f, scale = 0.0f;
    for (uint i = lane; i < count; i += RUBBLE_GROUP_BODIES) {
        const BodyMass m = masses[i];
        energies[i] = 0.0f;
        if (!(m.inverseMass > 0.0f)) continue;
        const BodyVelocity v = velocities[i];
        const BodyMomentum p = momenta[i];
        const float4 x = poses[i].position;
        const float4 kinetic = v.linear * p.linear + v.angular * p.angular;
        const float4 potential = gravity * x * -m.mass;
        const float4 terms = kinetic * 0.5f + potential;
        const float energy = terms.x + terms.y + terms.z;
        energies[i] = energy;
        // Kahan's sum: the part of each energy the running sum rounds away is kept apart.
        const float e = energy - lost;
        const float next = sum + e;
        lost = (next - sum) - e;
        sum = next;
        const float4 size = fabs(kinetic) * 0.5f + fabs(potential);
        scale += size.x + size.y + size.z;
    }
    totals[lane] = sum;
    scales[lane] = scale;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint width = RUBBLE_GROUP_BODIES / 2; width > 0; width >>= 1) {
        if (lane < width) {
            totals[lane] += totals[lane + width];
            scales[lane] += scales[lane + width];
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lane == 0) {
        const float total = totals[0];
        status[RUBBLE_STATUS_ENERGY] = as_uint(total);
        status[RUBBLE_STATUS_ENERGY_SCALE] = as_uint(scales[0]);
        lower = restart != 0u || total < lowest[0];
        if (lower) lowest[0] = total;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (!lower) return;
    for (uint i = lane; i < count; i += RUBBLE_GROUP_BODIES) atLowest[i] = energies[i];
}
