// include/rubble/shared/pgs_row.h: the contact rows of projected Gauss-Seidel and their updates,
// per element. The CPU reference builds its rows with pgsContactRowItem
// (host/dynamics/contact_rows.cpp, stage 5) and sweeps them in host/dynamics/pgs.cpp; the device
// builds the same rows in kernels/pgs_rows.cl (buildPgsRows) and sweeps them (pgs_sweep.cl) with
// the updates below, which repeat the CPU's arithmetic operation for operation.
#pragma once

#include "rubble/shared/contact_row.h"

RUBBLE_SHARED_BEGIN

// Tangential speeds above this pick the sliding direction as the first tangent, m/s: the two
// friction rows are bounded separately, and a box bound is only exact along its axes.
#define RUBBLE_SLIDING_SPEED 1e-3f
// A point whose feature id is new takes over the impulses of last step's unmatched point of the
// same pair nearest to it in a's frame, if within this distance, m: clipping can renumber the
// features of a resting box whose corners sit exactly on another's edges.
#define RUBBLE_WARM_START_MATCH_DISTANCE 0.02f
// The split position pass stops when no push impulse changed by more than this in a sweep, N s.
#define RUBBLE_PUSH_TOLERANCE 1e-6f
// A device sweep without a push sweep beside it (kernels/pgs_sweep.cl, solvePgs).
#define RUBBLE_PGS_NO_PUSH 0xffffffffu

// A pair's summary word on the device (kernels/pgs_rows.cl, summarizePairs), which the host colors
// from: its point count in the low bits, and which of its bodies move in the solve. An element's
// `rows` word is the same word.
#define RUBBLE_PGS_POINTS 7u
#define RUBBLE_PGS_MOVES_A 8u
#define RUBBLE_PGS_MOVES_B 16u
// An element of the device's solve that is a joint (its index in the low bits), not a pair.
#define RUBBLE_PGS_JOINT_ELEMENT 0x80000000u
// How a sweep kernel's launch goes through its elements (its `mode` argument): one per
// work-item (a color), all of them in order on work-item 0 (the serial tail), or in blocks:
// work-item 0 of group g runs block g's elements in order (blockStarts), the blocks sharing no
// body that moves. The device's plan (kernels/coloring.cl) gives a launch a color by its index
// (`first`), whose range the launch reads from the color starts bound as blockStarts: its
// elements striding over the launch's work-items, or, for the overflow set, in order on
// work-item 0.
#define RUBBLE_PGS_PER_ITEM 0u
#define RUBBLE_PGS_SERIAL 1u
#define RUBBLE_PGS_BLOCKS 2u
#define RUBBLE_PGS_COLOR 3u
#define RUBBLE_PGS_OVERFLOW 4u

// 32 bytes: one element of the device's solve, in color order (the host makes them after
// coloring): a pair's contact rows, or a joint. Point k's rows (its normal row, its friction
// pair) and impulses are at normal[k]: an element of a color has its points' in a run of its own,
// an element of a block by point within the block's rows (every element's first point, then
// every second point, ...: the order a block's passes read them in, as the CPU's
// interleaveContactRows lays out its rows), so that each pass reads them front to back.
typedef struct PgsElement {
    uint a, b;     // body indices
    uint id;       // the pair's index, or RUBBLE_PGS_JOINT_ELEMENT | the joint's
    uint rows;     // the pair's summary word: RUBBLE_PGS_MOVES_* | points
    uint normal[4]; // each point's rows and impulses (0 past the points, and for a joint)
} PgsElement;
RUBBLE_STATIC_ASSERT_SIZE(PgsElement, 32);

// 80 bytes, not stored: one row's Jacobian along a unit direction d at the arms rA, rB.
typedef struct RowJacobian {
    float4 crossA, crossB; // r_a x d, r_b x d; zero for a body that does not move, m
    float4 turnA, turnB;   // I_a^-1 (r_a x d), I_b^-1 (r_b x d), 1/(kg m)
    float mass;            // 1 / (J M^-1 J^T), kg; 0 when neither body moves
    float pad0, pad1, pad2;
} RowJacobian;

// A body that does not move (inverse mass 0) has no velocity to read and takes no impulse: its
// parts are zero. ia, ib are the world inverse inertias.
RUBBLE_FN RowJacobian rowJacobianItem(float4 d, float4 rA, float4 rB, float inverseMassA,
                                      float inverseMassB, Mat3 ia, Mat3 ib) {
    const float4 zero = vec4(0.0f, 0.0f, 0.0f);
    RowJacobian j;
    j.crossA = inverseMassA > 0.0f ? cross3(rA, d) : zero;
    j.crossB = inverseMassB > 0.0f ? cross3(rB, d) : zero;
    j.turnA = inverseMassA > 0.0f ? mat3MulVec(ia, j.crossA) : zero;
    j.turnB = inverseMassB > 0.0f ? mat3MulVec(ib, j.crossB) : zero;
    const float k = inverseMassA + inverseMassB + dot3(j.crossA, j.turnA) + dot3(j.crossB, j.turnB);
    j.mass = k > 0.0f ? 1.0f / k : 0.0f;
    j.pad0 = j.pad1 = j.pad2 = 0.0f;
    return j;
}

// Velocity of b's material point at rB relative to a's at rA, world, m/s.
RUBBLE_FN float4 pointRelativeVelocityItem(BodyVelocity va, BodyVelocity vb, float4 rA, float4 rB) {
    return sub4(add4(vb.linear, cross3(vb.angular, rB)), add4(va.linear, cross3(va.angular, rA)));
}

// A body of infinite mass that turns: a kinematic one (static and sleeping bodies do not turn).
RUBBLE_FN int turningWallItem(BodyVelocity v, float inverseMass) {
    return inverseMass <= 0.0f &&
           (v.angular.x != 0.0f || v.angular.y != 0.0f || v.angular.z != 0.0f);
}

// A contact point's arm from a body's centre of mass x, world, m.
RUBBLE_FN float4 pgsArmItem(float4 point, float4 x) {
    return sub4(vec4(point.x, point.y, point.z), vec4(x.x, x.y, x.z));
}

// A contact point's bounce (bounceItem) at arms rA, rB with penetration `depth` along the unit
// normal n, from the bodies' velocities after this step's forces (va, vb) and before them
// (vaBefore, vbBefore). pgsContactRowItem stores it in its normal row; summarizePairs asks it
// before the rows are built, to know whether the restitution pass will run.
RUBBLE_FN Bounce pointBounceItem(float4 rA, float4 rB, float4 n, float depth, BodyVelocity va,
                                 BodyVelocity vb, BodyVelocity vaBefore, BodyVelocity vbBefore,
                                 float restitution, float dt) {
    const float normalSpeed = dot3(pointRelativeVelocityItem(va, vb, rA, rB), n);
    const float4 relativeBefore = pointRelativeVelocityItem(vaBefore, vbBefore, rA, rB);
    const float gap = -depth < 0.0f ? 0.0f : -depth; // std::max(-depth, 0)
    return bounceItem(restitution, -dot3(relativeBefore, n), -normalSpeed, gap, dt);
}

// 112 bytes: a contact point's normal row (the CPU's NormalRow). It acts on body b with +J and
// on body a with -J.
typedef struct PgsNormalRow {
    float4 normal;         // unit, world, from a to b
    float4 crossA, crossB; // r_a x n, r_b x n (zero for a body that does not move), m
    float4 turnA, turnB;   // I_a^-1 (r_a x n), I_b^-1 (r_b x n), 1/(kg m)
    float4 speeds;         // x: target speed, y: push speed (m/s); z, w: 1/m_a, 1/m_b (1/kg)
    float4 mass;           // x: effective mass, kg; y: bounce speed, z: bounce lift (m/s); w: 0
} PgsNormalRow;
RUBBLE_STATIC_ASSERT_SIZE(PgsNormalRow, 112);

// 192 bytes: the same point's two friction rows (the CPU's FrictionRows).
typedef struct PgsFrictionRows {
    float4 tangent[2]; // unit, world; tangent[1] = n x tangent[0]
    float4 crossA[2], crossB[2];
    float4 turnA[2], turnB[2];
    float4 mass;        // x, y: effective masses, kg; z: friction coefficient; w: 0
    float4 inverseMass; // x, y: 1/m_a, 1/m_b (1/kg); z, w: 0
} PgsFrictionRows;
RUBBLE_STATIC_ASSERT_SIZE(PgsFrictionRows, 192);

// 304 bytes, not stored as one: a point's rows as the builder returns them.
typedef struct PgsContactRow {
    PgsNormalRow normal;
    PgsFrictionRows friction;
} PgsContactRow;
RUBBLE_STATIC_ASSERT_SIZE(PgsContactRow, 304);

// The rows of a manifold point at `point` (world, m) with penetration `depth` (m) along the
// manifold's unit normal n (from a to b), for bodies at xA, xB (centres of mass) with velocities
// va, vb (after this step's forces), velocities vaBefore, vbBefore before them, inverse masses
// (0: does not move) and world inverse inertias; friction sqrt(mu_a mu_b) and restitution
// max(e_a, e_b) already combined. The normal row's target and push are pgsNormalTargetItem's,
// its bounce bounceItem's from the approach before and after the forces across the gap; the
// first tangent follows the sliding direction when there is one, else fixedTangent (the
// manifold's perpendicularItem(n)). (Catto, "Iterative Dynamics with Temporal Coherence",
// GDC 2005; "Modeling and Solving Constraints", GDC 2009.)
RUBBLE_FN PgsContactRow pgsContactRowItem(float4 point, float depth, float4 n, float4 xA, float4 xB,
                                          BodyVelocity va, BodyVelocity vb, BodyVelocity vaBefore,
                                          BodyVelocity vbBefore, float inverseMassA,
                                          float inverseMassB, Mat3 ia, Mat3 ib, float friction,
                                          float restitution, float baumgarte, float slop, float dt,
                                          float4 fixedTangent) {
    PgsContactRow r;
    const float4 rA = pgsArmItem(point, xA), rB = pgsArmItem(point, xB);
    const float4 relative = pointRelativeVelocityItem(va, vb, rA, rB);
    const float normalSpeed = dot3(relative, n);

    const RowJacobian jn = rowJacobianItem(n, rA, rB, inverseMassA, inverseMassB, ia, ib);
    r.normal.normal = vec4(n.x, n.y, n.z);
    r.normal.crossA = jn.crossA;
    r.normal.crossB = jn.crossB;
    r.normal.turnA = jn.turnA;
    r.normal.turnB = jn.turnB;
    const NormalTarget t = pgsNormalTargetItem(depth, baumgarte, slop, dt);
    r.normal.speeds = make4(t.target, t.push, inverseMassA, inverseMassB);
    const Bounce bounce =
        pointBounceItem(rA, rB, n, depth, va, vb, vaBefore, vbBefore, restitution, dt);
    r.normal.mass = make4(jn.mass, bounce.speed, bounce.lift, 0.0f);

    // Tangents: along the sliding velocity when there is one, else the fixed basis.
    const float4 sliding = sub4(relative, scale4(n, normalSpeed));
    const float slidingSpeed = length3(sliding);
    float4 t0 = fixedTangent;
    if (slidingSpeed > RUBBLE_SLIDING_SPEED)
        t0 = vec4(sliding.x / slidingSpeed, sliding.y / slidingSpeed, sliding.z / slidingSpeed);
    PgsFrictionRows* f = &r.friction;
    f->tangent[0] = vec4(t0.x, t0.y, t0.z);
    f->tangent[1] = cross3(n, t0);
    float tangentMass[2];
    for (int d = 0; d < 2; ++d) {
        const RowJacobian jt =
            rowJacobianItem(f->tangent[d], rA, rB, inverseMassA, inverseMassB, ia, ib);
        f->crossA[d] = jt.crossA;
        f->crossB[d] = jt.crossB;
        f->turnA[d] = jt.turnA;
        f->turnB[d] = jt.turnB;
        tangentMass[d] = jt.mass;
    }
    f->mass = make4(tangentMass[0], tangentMass[1], friction, 0.0f);
    f->inverseMass = make4(inverseMassA, inverseMassB, 0.0f, 0.0f);
    // A body that does not move but turns (a kinematic one) carries the contact point round with
    // it: its arm enters J v, while no impulse turns it (its turn stays 0).
    if (turningWallItem(va, inverseMassA)) {
        r.normal.crossA = cross3(rA, r.normal.normal);
        for (int d = 0; d < 2; ++d) f->crossA[d] = cross3(rA, f->tangent[d]);
    }
    if (turningWallItem(vb, inverseMassB)) {
        r.normal.crossB = cross3(rB, r.normal.normal);
        for (int d = 0; d < 2; ++d) f->crossB[d] = cross3(rB, f->tangent[d]);
    }
    return r;
}

// J v of a row along d: the relative velocity of b against a at the contact point, summed as
// the CPU's four-lane form does (d (v_b - v_a) + (r_b x d) w_b - (r_a x d) w_a, then x + y + z).
RUBBLE_FN float pgsRowSpeedItem(BodyVelocity a, BodyVelocity b, float4 d, float4 crossA,
                                float4 crossB) {
    const float x =
        d.x * (b.linear.x - a.linear.x) + crossB.x * b.angular.x - crossA.x * a.angular.x;
    const float y =
        d.y * (b.linear.y - a.linear.y) + crossB.y * b.angular.y - crossA.y * a.angular.y;
    const float z =
        d.z * (b.linear.z - a.linear.z) + crossB.z * b.angular.z - crossA.z * a.angular.z;
    return x + y + z;
}

// 64 bytes, not stored: the velocities of a row's two bodies.
typedef struct BodyVelocityPair {
    BodyVelocity a, b;
} BodyVelocityPair;

// M^-1 J^T lambda of one row on both bodies.
RUBBLE_FN BodyVelocityPair applyPgsRowItem(BodyVelocityPair v, float4 d, float4 turnA, float4 turnB,
                                           float inverseMassA, float inverseMassB, float lambda) {
    v.a.linear = sub4(v.a.linear, scale4(d, inverseMassA * lambda));
    v.a.angular = sub4(v.a.angular, scale4(turnA, lambda));
    v.b.linear = add4(v.b.linear, scale4(d, inverseMassB * lambda));
    v.b.angular = add4(v.b.angular, scale4(turnB, lambda));
    return v;
}

// 80 bytes, not stored: the velocities after one row update, with the row's new accumulated
// impulse and the change applied (N s).
typedef struct PgsUpdate {
    BodyVelocityPair v;
    float accumulated, applied;
    float pad0, pad1;
} PgsUpdate;

// A normal row's accumulated impulse going from `accumulated` to `total`: the change applied to
// both bodies' velocities v.
RUBBLE_FN PgsUpdate pgsNormalUpdateItem(PgsNormalRow r, BodyVelocityPair v, float accumulated,
                                        float total) {
    PgsUpdate u;
    u.applied = total - accumulated;
    u.accumulated = total;
    u.v = applyPgsRowItem(v, r.normal, r.turnA, r.turnB, r.speeds.z, r.speeds.w, u.applied);
    u.pad0 = u.pad1 = 0.0f;
    return u;
}

// One projected Gauss-Seidel update of a normal row on the velocities v (the bodies' own, or
// the split pass's push velocities) toward `target` (m/s): the accumulated impulse stays >= 0
// and the change is applied to both bodies.
RUBBLE_FN PgsUpdate solvePgsNormalItem(PgsNormalRow r, BodyVelocityPair v, float target,
                                       float accumulated, float relaxation) {
    const float speed = pgsRowSpeedItem(v.a, v.b, r.normal, r.crossA, r.crossB);
    const float sum = accumulated + r.mass.x * (target - speed) * relaxation;
    const float total = sum < 0.0f ? 0.0f : sum; // std::max's choice between signed zeros
    return pgsNormalUpdateItem(r, v, accumulated, total);
}

// Whether a normal row bounces in the restitution pass: it has a bounce speed and stopped its
// bodies in this step's solve (`impulse`, its accumulated normal impulse, > 0), so that they
// reached the contact (pgs.cpp, isBouncing).
RUBBLE_FN int pgsBouncesItem(PgsNormalRow r, float impulse) {
    return r.mass.y > 0.0f && impulse > 0.0f;
}

// The split pass's target of a row: its push speed, or for a row that bounces the larger of
// that and its bounce's lift, which carries the bodies from the contact to where the rebound has
// taken them by the step's end (solvePushes).
RUBBLE_FN float pgsPushTargetItem(PgsNormalRow r, float impulse) {
    if (!pgsBouncesItem(r, impulse)) return r.speeds.y;
    return r.speeds.y < r.mass.z ? r.mass.z : r.speeds.y; // std::max
}

// One update of the restitution pass on a row that bounces (solveRestitution): lambda_b =
// max(lambda_b + m_eff (bounceSpeed - J v), -lambda), with `impulse` lambda the solve's
// accumulated normal impulse, so that the two stay >= 0 together; applied to both bodies.
RUBBLE_FN PgsUpdate solvePgsBounceItem(PgsNormalRow r, BodyVelocityPair v, float accumulated,
                                       float impulse) {
    const float speed = pgsRowSpeedItem(v.a, v.b, r.normal, r.crossA, r.crossB);
    const float sum = accumulated + r.mass.x * (r.mass.y - speed);
    const float total = sum < -impulse ? -impulse : sum; // std::max(sum, -impulse)
    return pgsNormalUpdateItem(r, v, accumulated, total);
}

// The layer pass (host/dynamics/pgs.cpp, solveLayers): a row's upper body is this many times as
// heavy as its lower one before the pass takes it (kLayerMassRatio).
#define RUBBLE_LAYER_MASS_RATIO 10.0f
// "No layer": a body that nothing links to a body that does not move.
#define RUBBLE_NO_LAYER 0xffffffffu

// Whether a body of inverse mass upInverse sits on one of downInverse as the layer pass takes it:
// both move, and the upper one is RUBBLE_LAYER_MASS_RATIO times as heavy.
RUBBLE_FN int heavyOverItem(float upInverse, float downInverse) {
    return upInverse > 0.0f && downInverse >= RUBBLE_LAYER_MASS_RATIO * upInverse;
}

// One update of a normal row that moves only the body on the upper side (b when upperIsB), the
// other held as if it did not move, from the accumulated impulse `total` toward `target`, the
// sum clamped >= 0 (solveNormalRowOnto); `applied` 0 and nothing moved when the upper body
// cannot move.
RUBBLE_FN PgsUpdate solvePgsNormalOntoItem(PgsNormalRow r, BodyVelocityPair v, int upperIsB,
                                           float target, float total) {
    PgsUpdate u;
    u.v = v;
    u.accumulated = total;
    u.applied = 0.0f;
    u.pad0 = u.pad1 = 0.0f;
    const float speed = pgsRowSpeedItem(v.a, v.b, r.normal, r.crossA, r.crossB);
    const float k =
        upperIsB ? r.speeds.w +
                       (r.crossB.x * r.turnB.x + r.crossB.y * r.turnB.y + r.crossB.z * r.turnB.z)
                 : r.speeds.z +
                       (r.crossA.x * r.turnA.x + r.crossA.y * r.turnA.y + r.crossA.z * r.turnA.z);
    if (k <= 0.0f) return u;
    const float sum = total + (target - speed) / k;
    const float next = sum < 0.0f ? 0.0f : sum; // std::max(sum, 0)
    u.applied = next - total;
    u.accumulated = next;
    if (upperIsB) {
        u.v.b.linear = add4(v.b.linear, scale4(r.normal, r.speeds.w * u.applied));
        u.v.b.angular = add4(v.b.angular, scale4(r.turnB, u.applied));
    } else {
        u.v.a.linear = sub4(v.a.linear, scale4(r.normal, r.speeds.z * u.applied));
        u.v.a.angular = sub4(v.a.angular, scale4(r.turnA, u.applied));
    }
    return u;
}

// 80 bytes, not stored: the velocities after a point's friction update, with the two new
// accumulated impulses (x, y) and the larger |change| (z), N s.
typedef struct PgsFrictionUpdate {
    BodyVelocityPair v;
    float4 impulse;
} PgsFrictionUpdate;

// A point's two friction rows from the same velocities, each within the box |lambda_t| <=
// mu lambda_n (`normal`, this sweep's normal impulse), applied together.
RUBBLE_FN PgsFrictionUpdate solvePgsFrictionItem(PgsFrictionRows r, BodyVelocityPair v,
                                                 float normal, float impulse0, float impulse1,
                                                 float relaxation) {
    const float bound = r.mass.z * normal;
    const float speed0 = pgsRowSpeedItem(v.a, v.b, r.tangent[0], r.crossA[0], r.crossB[0]);
    const float speed1 = pgsRowSpeedItem(v.a, v.b, r.tangent[1], r.crossA[1], r.crossB[1]);
    const float change0 = -r.mass.x * speed0 * relaxation;
    const float change1 = -r.mass.y * speed1 * relaxation;
    const float sum0 = impulse0 + change0, sum1 = impulse1 + change1;
    const float after0 = sum0 < -bound ? -bound : (bound < sum0 ? bound : sum0); // std::clamp
    const float after1 = sum1 < -bound ? -bound : (bound < sum1 ? bound : sum1);
    const float applied0 = after0 - impulse0, applied1 = after1 - impulse1;
    const float4 push = add4(scale4(r.tangent[0], applied0), scale4(r.tangent[1], applied1));
    PgsFrictionUpdate u;
    u.v = v;
    u.v.a.linear = sub4(v.a.linear, scale4(push, r.inverseMass.x));
    u.v.a.angular =
        sub4(v.a.angular, add4(scale4(r.turnA[0], applied0), scale4(r.turnA[1], applied1)));
    u.v.b.linear = add4(v.b.linear, scale4(push, r.inverseMass.y));
    u.v.b.angular =
        add4(v.b.angular, add4(scale4(r.turnB[0], applied0), scale4(r.turnB[1], applied1)));
    u.impulse = vec4(after0, after1, fmax(fabs(applied0), fabs(applied1)));
    return u;
}

// 48 bytes: a point's impulses at the end of a step, kept for the next step's warm start (the
// CPU's ContactImpulse).
typedef struct PgsImpulse {
    float4 pointInA; // the contact point in a's frame, m
    float4 friction; // world, N s (the tangents change between steps)
    float normal;    // N s
    uint feature;    // the manifold point's feature id
    uint pad0, pad1;
} PgsImpulse;
RUBBLE_STATIC_ASSERT_SIZE(PgsImpulse, 48);

// 16 bytes, not stored: which of last step's points (index, or -1) each new point takes its
// impulses from.
typedef struct WarmStartMatch {
    int from[4];
} WarmStartMatch;

// Hands last step's points of a pair (`old`, `oldCount` of them) to this step's (`keys`,
// `count`): the same feature first, then the nearest unmatched old point within
// RUBBLE_WARM_START_MATCH_DISTANCE in a's frame (host/dynamics/contact_rows.cpp, warmStart).
RUBBLE_FN WarmStartMatch warmStartMatchItem(const PgsImpulse* keys, uint count,
                                            const PgsImpulse* old, uint oldCount) {
    WarmStartMatch m;
    int taken[4] = {0, 0, 0, 0};
    for (uint k = 0; k < 4u; ++k) m.from[k] = -1;
    for (uint k = 0; k < count; ++k)
        for (uint o = 0; o < oldCount; ++o)
            if (!taken[o] && old[o].feature == keys[k].feature) {
                m.from[k] = (int)o;
                taken[o] = 1;
                break;
            }
    for (uint k = 0; k < count; ++k) {
        if (m.from[k] >= 0) continue;
        float best = RUBBLE_WARM_START_MATCH_DISTANCE * RUBBLE_WARM_START_MATCH_DISTANCE;
        int pick = -1;
        for (uint o = 0; o < oldCount; ++o) {
            if (taken[o]) continue;
            const float4 d = sub4(old[o].pointInA, keys[k].pointInA);
            if (dot3(d, d) < best) {
                best = dot3(d, d);
                pick = (int)o;
            }
        }
        if (pick < 0) continue;
        m.from[k] = pick;
        taken[pick] = 1;
    }
    return m;
}

RUBBLE_SHARED_END
