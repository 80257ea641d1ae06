// include/rubble/shared/soft_step.h: the soft step's per-point and per-joint math on the device
// (kernels/soft_step.cl): soft contact points, their separation within the step, the soft
// normal, friction and restitution updates on the PGS rows (pgs_row.h), and the soft joint
// blocks. Each repeats the CPU's arithmetic (host/dynamics/soft_step.cpp) operation for
// operation, so that a block in the CPU's order steps the CPU's numbers.
#pragma once

#include "rubble/shared/pgs_joint.h"

RUBBLE_SHARED_BEGIN

// A contact against a body that does not move takes this many times the contact hertz (Box2D
// v3's static softness; host/dynamics/soft_step.cpp, kStillContactHertzScale).
#define RUBBLE_SOFT_STILL_HERTZ_SCALE 2.0f
// pi as the CPU's makeSoftness writes it.
#define RUBBLE_SOFT_PI 3.14159265358979f

// 64 bytes: what a soft contact point needs beyond its PGS rows, at the same index (the CPU's
// SoftContactPoint).
typedef struct SoftContact {
    float4 anchorA; // xyz: the point from a's centre of mass in a's frame, m; w: separation at
                    // the step's start, m (negative: overlap)
    float4 anchorB; // xyz: the same from b's in b's frame; w: normal speed of b against a before
                    // the step's forces, m/s
    float4 offsetA; // xyz: the point from a's centre of mass at the step's start, world, m;
                    // w: restitution max(e_a, e_b)
    float4 offsetB; // xyz: the same from b's; w: 0
} SoftContact;
RUBBLE_STATIC_ASSERT_SIZE(SoftContact, 64);

// A soft constraint's coefficients over a substep h (the CPU's Softness, makeSoftness): x the
// bias rate omega / a1 (1/s), y the mass scale a2 a3, z the impulse scale a3; {0, 1, 0} (rigid,
// no bias) when hertz is 0.
RUBBLE_FN float4 softnessItem(float hertz, float dampingRatio, float h) {
    if (hertz == 0.0f) return make4(0.0f, 1.0f, 0.0f, 0.0f);
    const float omega = 2.0f * RUBBLE_SOFT_PI * hertz;
    const float a1 = 2.0f * dampingRatio + h * omega;
    const float a2 = h * omega * a1;
    const float a3 = 1.0f / (1.0f + a2);
    return make4(omega / a1, a2 * a3, a3, 0.0f);
}

// The contact point of a manifold point at `point` (world, m) with penetration `depth` along the
// unit normal n, for bodies at poses pa, pb whose velocities before the step's forces were aa,
// ab (prepareSoftContacts).
RUBBLE_FN SoftContact softContactItem(float4 point, float depth, float4 n, BodyPose pa, BodyPose pb,
                                      BodyVelocity aa, BodyVelocity ab, float restitution) {
    const float4 rA = pgsArmItem(point, pa.position), rB = pgsArmItem(point, pb.position);
    SoftContact c;
    const float4 anchorA = quatRotateInverse(pa.orientation, rA);
    const float4 anchorB = quatRotateInverse(pb.orientation, rB);
    const float approach = dot3(pointRelativeVelocityItem(aa, ab, rA, rB), n);
    c.anchorA = make4(anchorA.x, anchorA.y, anchorA.z, -depth);
    c.anchorB = make4(anchorB.x, anchorB.y, anchorB.z, approach);
    c.offsetA = make4(rA.x, rA.y, rA.z, restitution);
    c.offsetB = vec4(rB.x, rB.y, rB.z);
    return c;
}

// The point's separation now (m): the start's, moved along the normal by the bodies' motion
// within the step (movedA, movedB: x - x_start; qa, qb: the orientations now), so that no new
// collision is needed between substeps.
RUBBLE_FN float softSeparationItem(SoftContact c, float4 n, float4 movedA, float4 qa, float4 movedB,
                                   float4 qb) {
    const float4 pointA = add4(vec4(movedA.x, movedA.y, movedA.z),
                               quatRotate(qa, vec4(c.anchorA.x, c.anchorA.y, c.anchorA.z)));
    const float4 pointB = add4(vec4(movedB.x, movedB.y, movedB.z),
                               quatRotate(qb, vec4(c.anchorB.x, c.anchorB.y, c.anchorB.z)));
    const float4 d = sub4(sub4(pointB, vec4(c.offsetB.x, c.offsetB.y, c.offsetB.z)),
                          sub4(pointA, vec4(c.offsetA.x, c.offsetA.y, c.offsetA.z)));
    return c.anchorA.w + dot3(n, d);
}

// 16 bytes, not stored: a contact point's settings in a pass: the soft spring of a point between
// moving bodies and of one against a body that does not move (softnessItem), 1/h (1/s), the
// largest push-out speed (m/s), and whether the pass is biased (1) or a relax pass (0).
typedef struct SoftPass {
    float4 soft, softStill;
    float inverseH, maxPushSpeed;
    int useBias, pad0;
} SoftPass;

// A normal row's settings in a pass (pointSoftness): x the bias speed (m/s), y the mass scale,
// z the impulse scale. A gap (separation > 0) is closed within the substep and no further,
// rigidly; an overlap is pushed out by the spring (biased pass) or held rigidly (relax pass).
RUBBLE_FN float4 softPointItem(PgsNormalRow r, float separation, SoftPass p) {
    float bias = 0.0f, massScale = 1.0f, impulseScale = 0.0f;
    if (separation > 0.0f) {
        bias = separation * p.inverseH;
    } else if (p.useBias) {
        const int still = r.speeds.z == 0.0f || r.speeds.w == 0.0f;
        const float4 soft = still ? p.softStill : p.soft;
        const float push = soft.x * separation;
        bias = push < -p.maxPushSpeed ? -p.maxPushSpeed : push; // std::max(push, -maxPush)
        massScale = soft.y;
        impulseScale = soft.z;
    }
    return make4(bias, massScale, impulseScale, 0.0f);
}

// One soft update of a normal row (solveContacts) at the point's settings `k` (softPointItem).
// The accumulated impulse stays >= 0.
RUBBLE_FN PgsUpdate solveSoftNormalItem(PgsNormalRow r, BodyVelocityPair v, float4 k,
                                        float accumulated) {
    const float speed = pgsRowSpeedItem(v.a, v.b, r.normal, r.crossA, r.crossB);
    const float change = -r.mass.x * k.y * (speed + k.x) - k.z * accumulated;
    const float sum = accumulated + change;
    const float total = sum < 0.0f ? 0.0f : sum; // std::max(sum, 0)
    return pgsNormalUpdateItem(r, v, accumulated, total);
}

// What a manifold's point adds to its joint update (solveManifoldNormals): x its row's speed
// plus bias plus spring times impulse (the slope along the shared direction), y its spring
// impulseScale / (massScale m_eff) (its diagonal term), for the settings `k` (softPointItem).
RUBBLE_FN float4 softManifoldTermItem(PgsNormalRow r, BodyVelocityPair v, float4 k,
                                      float accumulated) {
    const float spring = k.z / (k.y * r.mass.x);
    const float speed = pgsRowSpeedItem(v.a, v.b, r.normal, r.crossA, r.crossB);
    return make4(speed + k.x + spring * accumulated, spring, 0.0f, 0.0f);
}

// A point's two friction rows one after the other (solveContacts), each within |lambda_t| <=
// mu lambda_n (`normal`, the point's normal impulse now): the velocities and the new impulses in
// x, y; z the larger |change|, N s.
RUBBLE_FN PgsFrictionUpdate solveSoftFrictionItem(PgsFrictionRows r, BodyVelocityPair v,
                                                  float normal, float impulse0, float impulse1) {
    const float bound = r.mass.z * normal;
    float impulse[2];
    impulse[0] = impulse0;
    impulse[1] = impulse1;
    const float mass[2] = {r.mass.x, r.mass.y};
    float largest = 0.0f;
    for (int k = 0; k < 2; ++k) {
        const float speed = pgsRowSpeedItem(v.a, v.b, r.tangent[k], r.crossA[k], r.crossB[k]);
        const float sum = impulse[k] - mass[k] * speed;
        const float next = sum < -bound ? -bound : (bound < sum ? bound : sum); // std::clamp
        const float step = next - impulse[k];
        impulse[k] = next;
        v = applyPgsRowItem(v, r.tangent[k], r.turnA[k], r.turnB[k], r.inverseMass.x,
                            r.inverseMass.y, step);
        largest = fmax(largest, fabs(step));
    }
    PgsFrictionUpdate u;
    u.v = v;
    u.impulse = vec4(impulse[0], impulse[1], largest);
    return u;
}

// Restitution after the substeps (applyRestitution): a point that approached faster than the
// threshold before the step and pushed in a substep (`largest`, its largest normal impulse)
// leaves at -e times that speed; `applied` 0 and nothing changed otherwise.
RUBBLE_FN PgsUpdate softRestitutionItem(PgsNormalRow r, SoftContact c, BodyVelocityPair v,
                                        float accumulated, float largest, float threshold) {
    const float restitution = c.offsetA.w, approach = c.anchorB.w;
    if (restitution == 0.0f || approach > -threshold || largest == 0.0f) {
        PgsUpdate u;
        u.v = v;
        u.accumulated = accumulated;
        u.applied = 0.0f;
        u.pad0 = u.pad1 = 0.0f;
        return u;
    }
    const float speed = pgsRowSpeedItem(v.a, v.b, r.normal, r.crossA, r.crossB);
    const float change = -r.mass.x * (speed + restitution * approach);
    const float sum = accumulated + change;
    const float total = sum < 0.0f ? 0.0f : sum;
    return pgsNormalUpdateItem(r, v, accumulated, total);
}

// One soft update of a joint at the bodies' poses now (pa, pb; `row` made there by
// prepareJointItem, with the accumulated impulses): the hinge's two angular rows as a 2x2
// block, then the anchor's three rows as a 3x3 block, soft toward C = 0 (`soft`: softnessItem's
// bias rate, mass and impulse scales; {0, 1, 0} in a relax pass). The largest |change| (N s) in
// w of pointImpulse.
RUBBLE_FN PgsJointUpdate solveSoftJointItem(BodyVelocityPair v, PgsJoint j, PgsJointRow r,
                                            BodyPose pa, BodyPose pb, JacobiBody ja, JacobiBody jb,
                                            float4 soft) {
    PgsJointUpdate u;
    u.v = v;
    u.pointImpulse = r.pointImpulse;
    u.turnImpulse = r.turnImpulse;
    if (r.state.x == 0.0f) {
        u.pointImpulse.w = 0.0f;
        return u;
    }
    const float biasRate = soft.x, massScale = soft.y, impulseScale = soft.z;
    float residual = 0.0f;
    if (j.type == RUBBLE_JOINT_HINGE) {
        const float4 a1 = quatRotate(pa.orientation, j.axisA);
        const float c0 = dot3(a1, quatRotate(pb.orientation, j.perpB[0]));
        const float c1 = dot3(a1, quatRotate(pb.orientation, j.perpB[1]));
        const float4 dw = sub4(u.v.a.angular, u.v.b.angular);
        const float s0 = dot3(r.turn[0], dw) + biasRate * c0;
        const float s1 = dot3(r.turn[1], dw) + biasRate * c1;
        const float4 m = r.turnMass;
        const float4 impulse =
            vec4(-massScale * (m.x * s0 + m.y * s1) - impulseScale * r.turnImpulse.x,
                 -massScale * (m.z * s0 + m.w * s1) - impulseScale * r.turnImpulse.y, 0.0f);
        u.turnImpulse = add4(u.turnImpulse, impulse);
        u.v = applyJointTurnItem(u.v, r, impulse, ja, jb);
        residual = fmax(fabs(impulse.x), fabs(impulse.y));
    }
    const float4 speed = sub4(add4(u.v.b.linear, cross3(u.v.b.angular, r.rb)),
                              add4(u.v.a.linear, cross3(u.v.a.angular, r.ra)));
    const float4 separation = sub4(add4(vec4(pb.position.x, pb.position.y, pb.position.z), r.rb),
                                   add4(vec4(pa.position.x, pa.position.y, pa.position.z), r.ra));
    const float4 target = add4(speed, scale4(separation, biasRate));
    const float4 solved = mat3MulVec(r.pointMass, target);
    const float4 impulse = sub4(scale4(solved, -massScale), scale4(r.pointImpulse, impulseScale));
    const float4 change = vec4(impulse.x, impulse.y, impulse.z);
    u.pointImpulse = add4(vec4(u.pointImpulse.x, u.pointImpulse.y, u.pointImpulse.z), change);
    u.v = applyJointPointItem(u.v, r, change, ja, jb);
    residual = fmax(residual, fmax(fabs(change.x), fmax(fabs(change.y), fabs(change.z))));
    u.pointImpulse.w = residual;
    return u;
}

RUBBLE_SHARED_END
