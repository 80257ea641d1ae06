// include/rubble/shared/contact_row.h: contact rows of the Jacobi solver (OpenCL stage 5) and
// their per-element math: building a row, one projected Jacobi update, and the per-body
// gather. CPU twins in host/dynamics/jacobi.cpp; kernels in kernels/jacobi.cl.
#pragma once

#include "rubble/shared/body.h"
#include "rubble/shared/particle.h"

RUBBLE_SHARED_BEGIN

// 16 bytes: the solver's settings for one step, passed to kernels by value.
typedef struct SolverParams {
    float baumgarte;  // fraction of the penetration corrected per step, 0..1
    float slop;       // penetration left uncorrected, m
    float inverseDt;  // 1/s
    float relaxation; // scales each impulse update (1: none)
} SolverParams;
RUBBLE_STATIC_ASSERT_SIZE(SolverParams, 16);

// 128 bytes: one contact point as three rows, normal and two friction directions. Rows act on
// body a with -J and on body b with +J; impulses are accumulated and clamped as in PGS.
typedef struct ContactRow {
    float4 normal;   // unit, world, from a to b
    float4 tangent1; // unit, world, perpendicular to the normal
    float4 tangent2; // normal x tangent1
    float4 rA;       // contact point from a's centre of mass, world, m
    float4 rB;       // contact point from b's centre of mass, world, m
    float4 lambda;   // accumulated impulses: x normal, y tangent1, z tangent2, N s
    float4 mass;     // effective mass of each row, 1 / (J M^-1 J^T) with split masses, kg
    uint a, b;       // body indices
    float bias;      // normal row: the relative normal velocity it must reach, m/s (negated)
    float friction;  // Coulomb coefficient
} ContactRow;
RUBBLE_STATIC_ASSERT_SIZE(ContactRow, 128);

// The penetration a particle contact leaves to the Baumgarte term uncorrected: the scene's slop,
// or a tenth of the particle spacing (a fifth of a particle's radius) when that is more. Bodies
// made of spheres rest on bumps a few centimetres deep, and a solve of a few sweeps does not hold
// a deep pile exactly: asked to push every resting contact out, it turns the push into motion
// and the pile creeps for good. Slop as the allowed penetration: Catto, "Iterative dynamics with
// temporal coherence", 2005; docs/opencl.md, "Particle contacts".
#define RUBBLE_PARTICLE_SLOP_FRACTION 0.1f
RUBBLE_FN float particleSlopItem(float slop, float particleSpacing) {
    return fmax(slop, RUBBLE_PARTICLE_SLOP_FRACTION * particleSpacing);
}

// Projected Gauss-Seidel's normal row (host/dynamics/contact_rows.cpp on the CPU, buildPgsRows
// on the device; both call pgsNormalTargetItem and bounceItem, so that a change of the rule lands
// in both). The split position pass pushes at most this fast, m/s: a deep penetration (a fast
// body caught a step late) is undone over a few steps instead of throwing the bodies apart.
#define RUBBLE_MAX_PUSH_SPEED 2.0f

// 8 bytes, not stored: what a PGS normal row aims at.
typedef struct NormalTarget {
    float target; // normal velocity the velocity solve aims at, m/s
    float push;   // Baumgarte speed of the split position pass, m/s (>= 0)
} NormalTarget;

// The target of a contact point's normal row from its depth (m; negative: a gap): stop a
// touching approach (0), or let a gap close within the step and no further (depth / dt); the
// penetration beyond the slop goes to the split position pass, at min(beta/dt (depth - slop),
// RUBBLE_MAX_PUSH_SPEED) (Catto, "Fast and Simple Physics using Sequential Impulses", GDC 2006).
// A bounce is not the velocity solve's: see bounceItem.
RUBBLE_FN NormalTarget pgsNormalTargetItem(float depth, float baumgarte, float slop, float dt) {
    NormalTarget t;
    if (depth >= 0.0f) {
        const float beyond = depth - slop;
        const float push = baumgarte / dt * (beyond < 0.0f ? 0.0f : beyond);  // std::max
        t.push = RUBBLE_MAX_PUSH_SPEED < push ? RUBBLE_MAX_PUSH_SPEED : push; // std::min
        t.target = 0.0f;
    } else {
        t.push = 0.0f;
        t.target = depth / dt;
    }
    return t;
}

// 8 bytes, not stored: a contact point's bounce, for the restitution pass after the positions
// moved.
typedef struct Bounce {
    float speed; // normal velocity to leave with, m/s (0: no bounce)
    float lift;  // the split pass's speed that lifts the bodies off the contact, m/s
} Bounce;

// A bounce from the contact, for a point whose bodies approach at `before` m/s before this
// step's forces and `after` after them (positive: closing) across `gap` m. The forces'
// acceleration a = (after - before) / dt carries the approach over the gap, and only a meeting
// faster than RUBBLE_RESTITUTION_THRESHOLD bounces (at rest before the forces, nothing does,
// whatever dt). Symplectic Euler's positions are samples at the steps of the path whose velocity
// at the step's start is the stored one plus half a step of a, u0 = before + a dt / 2: on it the
// bodies meet at t_c = 2 gap / (u0 + u_c) with u_c = sqrt(u0^2 + 2 a gap) and leave at e u_c.
// The stored velocity is e times the approach before the forces, as an impulse-based engine
// leaves a contact (a ball with e = 1 leaves at the speed it arrived with), and the split pass
// lifts the bodies to where that speed's later steps reach the path's apex: the rebound keeps
// e^2 of the drop height to round-off. The comparisons are std::max's (the same signed zeros and
// NaNs on the host and the device).
RUBBLE_FN Bounce bounceItem(float restitution, float before, float after, float gap, float dt) {
    Bounce none;
    none.speed = 0.0f;
    none.lift = 0.0f;
    if (restitution <= 0.0f) return none;
    const float closing = before < 0.0f ? 0.0f : before;
    const float a = (after - before) / dt;
    const float meeting = closing * closing + 2.0f * a * gap;
    if (meeting <= RUBBLE_RESTITUTION_THRESHOLD * RUBBLE_RESTITUTION_THRESHOLD) return none;
    const float u0 = closing + 0.5f * a * dt;
    const float reach = u0 * u0 + 2.0f * a * gap;
    if (u0 <= 0.0f || reach <= 0.0f) return none;
    const float uc = sqrt(reach);
    const float tc = 2.0f * gap / (u0 + uc);
    const float left = dt - tc;
    const float tau = left < 0.0f ? 0.0f : left;
    Bounce b;
    b.speed = restitution * closing;
    if (b.speed <= 0.0f) return none;
    // On the continuous path the bodies leave the contact at e u_c and are e u_c tau - a tau^2 / 2
    // apart at the step's end. Under a steady pull (a > 0) the steps after this one take the
    // stored speed v down by a dt a step, and rise K v dt - a dt^2 K (K + 1) / 2 before they turn
    // (K = floor(v / (a dt))): the bodies end this step that much below the path's apex,
    // (e u_c)^2 / (2 a) above the contact.
    float rise = restitution * uc * tau - 0.5f * a * tau * tau;
    const float perStep = a * dt;
    if (perStep > 0.0f && b.speed < 1.0e4f * perStep) {
        const float k = floor(b.speed / perStep);
        const float later = dt * (k * b.speed - 0.5f * perStep * k * (k + 1.0f));
        const float leave = restitution * uc;
        rise = leave * leave / (2.0f * a) - later;
    }
    b.lift = (rise < 0.0f ? 0.0f : rise) / dt;
    return b;
}

// A unit vector perpendicular to n (Catto's basis: the larger of two candidate axes).
RUBBLE_FN float4 perpendicularItem(float4 n) {
    if (fabs(n.x) >= 0.57735f) return normalize3(vec4(n.y, -n.x, 0.0f));
    return normalize3(vec4(0.0f, n.z, -n.y));
}

// 1 / (J M^-1 J^T) of the row along direction d at arms rA, rB, with each body's inverse mass
// and inertia multiplied by its share count (mass splitting, Tonge et al. 2012, eq. 10).
RUBBLE_FN float rowMassItem(float4 d, float4 rA, float4 rB, float invMassA, Mat3 invIA,
                            float invMassB, Mat3 invIB, float splitA, float splitB) {
    const float4 ca = cross3(rA, d), cb = cross3(rB, d);
    const float k = splitA * (invMassA + dot3(ca, mat3MulVec(invIA, ca))) +
                    splitB * (invMassB + dot3(cb, mat3MulVec(invIB, cb)));
    return k > 0.0f ? 1.0f / k : 0.0f;
}

// Velocity of b's contact point relative to a's, world, m/s.
RUBBLE_FN float4 relativeVelocityItem(ContactRow r, BodyVelocity va, BodyVelocity vb) {
    const float4 pa = add4(va.linear, cross3(va.angular, r.rA));
    const float4 pb = add4(vb.linear, cross3(vb.angular, r.rB));
    return sub4(pb, pa);
}

// A row for a contact at `point` (world, m) with penetration `depth` (m) and normal from a to b.
// Baumgarte bias corrects beta (depth - slop) / dt; restitution asks for -e vn when the bodies
// approach faster than RUBBLE_RESTITUTION_THRESHOLD, vn measured with va, vb: the bodies'
// velocities before this step's forces. `warm` holds impulses to start from (x, y, z as in
// lambda). xA, xB are the bodies' centres of mass (world, m), invMassA/B their inverse masses
// (1/kg) and invIA/B their inverse inertia in the world frame.
RUBBLE_FN ContactRow makeContactRowItem(float4 point, float4 normal, float depth, uint a, uint b,
                                        float4 xA, float4 xB, BodyVelocity va, BodyVelocity vb,
                                        float invMassA, float invMassB, Mat3 invIA, Mat3 invIB,
                                        float splitA, float splitB, float friction,
                                        float restitution, SolverParams p, float4 warm) {
    ContactRow r;
    r.normal = vec4(normal.x, normal.y, normal.z);
    r.tangent1 = perpendicularItem(r.normal);
    r.tangent2 = cross3(r.normal, r.tangent1);
    r.rA = sub4(vec4(point.x, point.y, point.z), vec4(xA.x, xA.y, xA.z));
    r.rB = sub4(vec4(point.x, point.y, point.z), vec4(xB.x, xB.y, xB.z));
    r.a = a;
    r.b = b;
    r.friction = friction;
    r.mass = vec4(rowMassItem(r.normal, r.rA, r.rB, invMassA, invIA, invMassB, invIB, splitA,
                              splitB),
                  rowMassItem(r.tangent1, r.rA, r.rB, invMassA, invIA, invMassB, invIB, splitA,
                              splitB),
                  rowMassItem(r.tangent2, r.rA, r.rB, invMassA, invIA, invMassB, invIB, splitA,
                              splitB));
    const float penetration = depth - p.slop;
    r.bias = penetration > 0.0f ? -p.baumgarte * p.inverseDt * penetration : 0.0f;
    const float vn = dot3(relativeVelocityItem(r, va, vb), r.normal);
    if (vn < -RUBBLE_RESTITUTION_THRESHOLD && restitution * vn < r.bias) r.bias = restitution * vn;
    r.lambda = vec4(warm.x, warm.y, warm.z);
    return r;
}

// One projected Jacobi update of a row from the velocities of the last iteration: the normal
// impulse stays >= 0, each friction impulse within +-mu lambda_n (Catto 2005, "Iterative
// dynamics with temporal coherence", sequential impulses with accumulated clamping).
RUBBLE_FN float4 solveContactItem(ContactRow r, BodyVelocity va, BodyVelocity vb,
                                  float relaxation) {
    const float4 v = relativeVelocityItem(r, va, vb);
    const float ln = fmax(r.lambda.x - relaxation * r.mass.x * (dot3(v, r.normal) + r.bias), 0.0f);
    const float limit = r.friction * ln;
    const float l1 = fmin(fmax(r.lambda.y - relaxation * r.mass.y * dot3(v, r.tangent1), -limit),
                          limit);
    const float l2 = fmin(fmax(r.lambda.z - relaxation * r.mass.z * dot3(v, r.tangent2), -limit),
                          limit);
    return vec4(ln, l1, l2);
}

// The impulse a row's accumulated lambda puts on body b (body a gets its negative), N s.
RUBBLE_FN float4 rowImpulseItem(ContactRow r) {
    return add4(add4(scale4(r.normal, r.lambda.x), scale4(r.tangent1, r.lambda.y)),
                scale4(r.tangent2, r.lambda.z));
}

// 48 bytes, made once per step (stage buildJacobiRows, prepareJacobiBodies on the device): what
// the rows and the gathers need of a body: its inverse inertia in the world frame (rows,
// 1/(kg m^2)) with its inverse mass (1/kg) in the first row's w. mat3MulVec ignores w.
typedef struct JacobiBody {
    Mat3 inverseInertiaWorld;
} JacobiBody;
RUBBLE_STATIC_ASSERT_SIZE(JacobiBody, 48);

// Whether the body takes part in this step's solve as a body that moves (a sleeping, static or
// kinematic one has a zero inverse mass in its record: a wall).
RUBBLE_FN int movesInSolveItem(JacobiBody j) { return j.inverseInertiaWorld.r0.w > 0.0f; }

RUBBLE_FN JacobiBody jacobiBodyItem(BodyMass m, float4 orientation) {
    JacobiBody j;
    j.inverseInertiaWorld = inverseInertiaWorldItem(m, orientation);
    j.inverseInertiaWorld.r0.w = m.inverseMass;
    return j;
}

// A row for a contact point from the bodies' positions, velocities before the step's forces and
// JacobiBody records: materials combine as sqrt(mu_a mu_b) and max(e_a, e_b) (surface x =
// friction, y = restitution); each body's mass is split among its `count` rows.
RUBBLE_FN ContactRow contactRowFromJacobiItem(ParticleContact c, float4 xA, float4 xB,
                                              BodyVelocity va, BodyVelocity vb, JacobiBody ja,
                                              JacobiBody jb, float4 surfaceA, float4 surfaceB,
                                              uint countA, uint countB, SolverParams p,
                                              float4 warm) {
    const float friction = sqrt(surfaceA.x * surfaceB.x);
    const float restitution = fmax(surfaceA.y, surfaceB.y);
    const float splitA = countA > 1u ? (float)countA : 1.0f;
    const float splitB = countB > 1u ? (float)countB : 1.0f;
    return makeContactRowItem(c.point, c.normal, c.point.w, c.a, c.b, xA, xB, va, vb,
                              ja.inverseInertiaWorld.r0.w, jb.inverseInertiaWorld.r0.w,
                              ja.inverseInertiaWorld, jb.inverseInertiaWorld, splitA, splitB,
                              friction, restitution, p, warm);
}

// The same from the bodies' poses and mass records.
RUBBLE_FN ContactRow contactRowFromContactItem(ParticleContact c, BodyPose pa, BodyPose pb,
                                               BodyVelocity va, BodyVelocity vb, BodyMass ma,
                                               BodyMass mb, float4 surfaceA, float4 surfaceB,
                                               uint countA, uint countB, SolverParams p,
                                               float4 warm) {
    return contactRowFromJacobiItem(c, pa.position, pb.position, va, vb,
                                    jacobiBodyItem(ma, pa.orientation),
                                    jacobiBodyItem(mb, pb.orientation), surfaceA, surfaceB, countA,
                                    countB, p, warm);
}

// The largest change of any of a row's three impulses, N s.
RUBBLE_FN float impulseChangeItem(float4 before, float4 after) {
    return fmax(fabs(after.x - before.x), fmax(fabs(after.y - before.y), fabs(after.z - before.z)));
}

// 32 bytes, not stored: what one row does to one of its bodies, N s and N m s.
typedef struct BodyImpulse {
    float4 linear;
    float4 angular;
} BodyImpulse;
RUBBLE_STATIC_ASSERT_SIZE(BodyImpulse, 32);

// The impulse `onB` of a row (rowImpulseItem) on its body a (side 0: the negative) or b (side
// 1), with the arm from that body's centre of mass to the contact point.
RUBBLE_FN BodyImpulse impulseOnBodyItem(float4 onB, float4 arm, uint side) {
    BodyImpulse i;
    i.linear = side ? onB : scale4(onB, -1.0f);
    i.angular = cross3(arm, i.linear);
    return i;
}

// A row's impulse on its body a (side 0: minus J^T lambda) or b (side 1).
RUBBLE_FN BodyImpulse rowImpulseOnBodyItem(ContactRow r, uint side) {
    return impulseOnBodyItem(rowImpulseItem(r), side ? r.rB : r.rA, side);
}

// Velocities after the summed impulse P (N s) and angular impulse H (N m s) of a body's rows:
// v = v0 + P / m, omega = omega0 + I_w^-1 H.
RUBBLE_FN BodyVelocity applyImpulseSumItem(BodyVelocity v0, float4 linear, float4 angular,
                                           float inverseMass, Mat3 inverseInertiaWorld) {
    BodyVelocity v;
    v.linear = add4(v0.linear, scale4(linear, inverseMass));
    v.angular = add4(v0.angular, mat3MulVec(inverseInertiaWorld, angular));
    return v;
}

RUBBLE_SHARED_END
