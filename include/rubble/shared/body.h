// include/rubble/shared/body.h: rigid-body records and their per-element integration, compiled by
// the host (core/integrate.cpp, the CPU twin) and by kernels/integrate.cl (OpenCL stages 1 and 6).
#pragma once

#include "rubble/shared/constants.h"
#include "rubble/shared/math.h"

RUBBLE_SHARED_BEGIN

// Body flags (BodyMass.flags on the host; the device keeps them in an array of their own).
#define RUBBLE_BODY_STATIC 1u    // infinite mass, never moves
#define RUBBLE_BODY_ASLEEP 2u    // skipped by integration and the solver until woken
#define RUBBLE_BODY_KINEMATIC 4u // infinite mass, moved by its velocities or by the host
#define RUBBLE_BODY_ABSENT 8u    // device: a kinematic body far from everything, not collided
#define RUBBLE_BODY_WAKING 16u   // device: a kinematic body that moves: it wakes what it touches

// A body that integrates, collides on its own initiative and has its rows gathered: dynamic,
// awake and not moved by the host.
RUBBLE_FN int activeBodyItem(uint flags) {
    return (flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP | RUBBLE_BODY_KINEMATIC |
                     RUBBLE_BODY_ABSENT)) == 0u;
}

// A body whose rows are listed for a gather: an active body (its velocity) or a kinematic one
// (the impulses it takes, for the host); sleeping and static bodies take part as walls.
RUBBLE_FN int listedBodyItem(uint flags) {
    return (flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP | RUBBLE_BODY_ABSENT)) == 0u;
}

// 32 bytes: where a body is. position is the centre of mass, world frame, m (w = 0);
// orientation is the unit quaternion (x, y, z, w) from the body frame to the world frame.
typedef struct BodyPose {
    float4 position;
    float4 orientation;
} BodyPose;
RUBBLE_STATIC_ASSERT_SIZE(BodyPose, 32);

// 32 bytes: derived velocities, world frame: linear m/s, angular rad/s (w = 0).
typedef struct BodyVelocity {
    float4 linear;
    float4 angular;
} BodyVelocity;
RUBBLE_STATIC_ASSERT_SIZE(BodyVelocity, 32);

// A velocity that is not zero: a kinematic body with it moves, and wakes what it touches.
RUBBLE_FN int movesAtAllItem(BodyVelocity v) {
    return dot3(v.linear, v.linear) > 0.0f || dot3(v.angular, v.angular) > 0.0f;
}

// 32 bytes: the state's momenta, world frame: linear P in kg m/s, angular L in kg m^2/s.
typedef struct BodyMomentum {
    float4 linear;
    float4 angular;
} BodyMomentum;
RUBBLE_STATIC_ASSERT_SIZE(BodyMomentum, 32);

// 32 bytes: force (N) and torque (N m) about the centre of mass, world frame, for this step.
typedef struct BodyForce {
    float4 force;
    float4 torque;
} BodyForce;
RUBBLE_STATIC_ASSERT_SIZE(BodyForce, 32);

// 112 bytes, immutable after load: body-frame inertia about the centre of mass (kg m^2), its
// inverse, and the mass (kg). Static bodies have zero inverses.
typedef struct BodyMass {
    Mat3 inertiaBody;
    Mat3 inverseInertiaBody;
    float mass;
    float inverseMass;
    uint flags;
    uint pad0;
} BodyMass;
RUBBLE_STATIC_ASSERT_SIZE(BodyMass, 112);

// A body's mass record as a wall: infinite mass and inertia (a sleeping body in a contact row).
RUBBLE_FN BodyMass wallMassItem(BodyMass m) {
    BodyMass w = m;
    w.inverseMass = 0.0f;
    w.inverseInertiaBody.r0 = make4(0.0f, 0.0f, 0.0f, 0.0f);
    w.inverseInertiaBody.r1 = make4(0.0f, 0.0f, 0.0f, 0.0f);
    w.inverseInertiaBody.r2 = make4(0.0f, 0.0f, 0.0f, 0.0f);
    return w;
}

// I_w^-1 = R I_b^-1 R^T.
RUBBLE_FN Mat3 inverseInertiaWorldItem(BodyMass m, float4 orientation) {
    return mat3RotateTensor(mat3FromQuat(orientation), m.inverseInertiaBody);
}

// Momenta after one step of the external forces: P += dt (F + m g), L += dt tau.
RUBBLE_FN BodyMomentum integrateMomentumItem(BodyMomentum p, BodyForce f, BodyMass m,
                                             float4 gravity, float dt) {
    if (m.inverseMass == 0.0f) return p;
    BodyMomentum r;
    r.linear = add4(p.linear, scale4(add4(f.force, scale4(gravity, m.mass)), dt));
    r.angular = add4(p.angular, scale4(f.torque, dt));
    return r;
}

// A body's velocities at the start of the step, before its forces: v = P / m (an explosion or an
// impulse from the host may have changed P since the velocities were derived; neither changes
// L) and the angular velocity as derived.
RUBBLE_FN BodyVelocity beforeForcesItem(BodyMomentum p, BodyMass m, BodyVelocity v) {
    BodyVelocity r;
    r.linear = scale4(p.linear, m.inverseMass);
    r.angular = v.angular;
    return r;
}

// Derived velocities: v = P / m, omega = I_w^-1 L.
RUBBLE_FN BodyVelocity velocityFromMomentumItem(BodyMomentum p, BodyMass m, float4 orientation) {
    BodyVelocity v;
    v.linear = scale4(p.linear, m.inverseMass);
    v.angular = mat3MulVec(inverseInertiaWorldItem(m, orientation), p.angular);
    return v;
}

// Momenta changed by a velocity change dv (from constraint impulses): P += m dv, L += I_w dw.
// Adding the change keeps untouched bodies' momenta bit for bit.
RUBBLE_FN BodyMomentum absorbVelocityChangeItem(BodyMomentum p, BodyVelocity before,
                                                BodyVelocity after, BodyMass m, float4 orientation) {
    if (m.inverseMass == 0.0f) return p;
    const float4 dv = sub4(after.linear, before.linear);
    const float4 dw = sub4(after.angular, before.angular);
    const Mat3 inertiaWorld = mat3RotateTensor(mat3FromQuat(orientation), m.inertiaBody);
    BodyMomentum r;
    r.linear = add4(p.linear, scale4(dv, m.mass));
    r.angular = add4(p.angular, mat3MulVec(inertiaWorld, dw));
    return r;
}

// Explicit Euler positions: x += dt v, q += dt/2 (omega, 0) q, renormalised, with the velocities
// the step started with.
RUBBLE_FN BodyPose integratePositionItem(BodyPose pose, BodyVelocity v, float dt) {
    BodyPose r;
    r.position = add4(pose.position, scale4(v.linear, dt));
    r.orientation = quatIntegrate(pose.orientation, v.angular, dt);
    return r;
}

// Symplectic Euler positions: x += dt v with the new velocity; the orientation turns with the
// angular velocity of the new momentum L at the half-step orientation (explicit midpoint), since
// omega = I_w(q)^-1 L changes as the body turns. The first-order update pumps energy into a
// tumbling body step after step; turning at the half-step orientation keeps its energy close to
// constant (docs/integrators.md compares the two).
RUBBLE_FN BodyPose integratePositionSymplecticItem(BodyPose pose, BodyVelocity v, BodyMomentum p,
                                                   BodyMass m, float dt) {
    BodyPose r;
    r.position = add4(pose.position, scale4(v.linear, dt));
    const float4 halfway = quatIntegrate(pose.orientation, v.angular, 0.5f * dt);
    const float4 omegaHalf = mat3MulVec(inverseInertiaWorldItem(m, halfway), p.angular);
    r.orientation = quatIntegrate(pose.orientation, omegaHalf, dt);
    return r;
}

RUBBLE_SHARED_END
