// kernels/forces.cl: entry points of OpenCL stage 1's host inputs (applyForces): explosions,
// and the bodies the host steps placed where it has them. The explosion's math is in
// rubble/shared/events.h, shared with its CPU path in host/dynamics/forces.cpp.
#include "rubble/shared/events.h"
#include "rubble/shared/obstacle.h"

// An explosion (centre xyz, reach in w, m; impulse N s) on every dynamic body it reaches, asleep
// or not: the impulse goes into the momenta and the body wakes.
__kernel void applyExplosion(const uint count, const float4 explosion, const float impulse,
                             __global const BodyPose* poses, __global uint* flags,
                             __global BodyMomentum* momenta, __global float* slowFor) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const uint f = flags[i];
    if (f & (RUBBLE_BODY_STATIC | RUBBLE_BODY_KINEMATIC)) return;
    const float4 j = explosionImpulseItem(poses[i].position, explosion, impulse, explosion.w);
    if (j.w == 0.0f) return; // out of reach
    momenta[i].linear = add4(momenta[i].linear, vec4(j.x, j.y, j.z));
    flags[i] = f & ~RUBBLE_BODY_ASLEEP;
    slowFor[i] = 0.0f;
}

// Velocities the host gave the scene's kinematic bodies since the last step, with their flags
// (moving ones wake what they touch): the body's pose stays the device's.
__kernel void setKinematicVelocities(const uint count, __global const ObstacleState* states,
                                     __global BodyVelocity* velocities, __global uint* flags) {
    const uint k = get_global_id(0);
    if (k >= count) return;
    const ObstacleState o = states[k];
    velocities[o.body] = o.velocity;
    flags[o.body] = o.flags;
}

// The host's bodies at the start of the step, as kinematic bodies: infinite mass on the device,
// with the velocity the host gave them.
__kernel void placeObstacles(const uint count, __global const ObstacleState* obstacles,
                             __global BodyPose* poses, __global BodyVelocity* velocities,
                             __global uint* flags) {
    const uint k = get_global_id(0);
    if (k >= count) return;
    const ObstacleState o = obstacles[k];
    poses[o.body] = o.pose;
    velocities[o.body] = o.velocity;
    flags[o.body] = o.flags;
}
