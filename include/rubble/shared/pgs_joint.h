// include/rubble/shared/pgs_joint.h: ball and hinge joints on the device, per element: their
// velocity rows in projected Gauss-Seidel (kernels/pgs_sweep.cl, the same colored sweeps as the
// contacts) and their position projection after integratePositions. A float port of the CPU's
// host/dynamics/joints.cpp (prepareJoints, warmStartJoints, solveJointVelocity) and of
// host/dynamics/joint_positions.cpp's joint-by-joint projection; tests/gpu/pgs_twin_test.cpp
// holds them to the CPU's.
#pragma once

#include "rubble/shared/pgs_row.h"

RUBBLE_SHARED_BEGIN

#define RUBBLE_JOINT_BALL 0u
#define RUBBLE_JOINT_HINGE 1u

// Position projection (host/dynamics/joint_positions.cpp): a joint is done when its anchors
// are within RUBBLE_JOINT_LINEAR_TOLERANCE (m) and its hinge rows within
// RUBBLE_JOINT_ANGULAR_TOLERANCE (the cosine between the axis and a perpendicular); one
// projection moves an anchor by at most RUBBLE_JOINT_MAX_LINEAR_CORRECTION (m) and turns a body by
// at most RUBBLE_JOINT_MAX_ANGULAR_CORRECTION (rad); pivots below RUBBLE_JOINT_PIVOT_TOLERANCE of
// the largest diagonal entry are redundant rows, left out.
#define RUBBLE_JOINT_LINEAR_TOLERANCE 1e-5f
#define RUBBLE_JOINT_ANGULAR_TOLERANCE 1e-5f
#define RUBBLE_JOINT_MAX_LINEAR_CORRECTION 0.2f
#define RUBBLE_JOINT_MAX_ANGULAR_CORRECTION 0.25f
#define RUBBLE_JOINT_PIVOT_TOLERANCE ((JointReal)1e-9)
// Newton steps of the position projection per step (it stops once every joint holds).
#define RUBBLE_JOINT_POSITION_ITERATIONS 20
// A joint group with at most this many rows is projected as one (its whole system solved
// directly); a larger one joint by joint (non-linear Gauss-Seidel).
#define RUBBLE_JOINT_DIRECT_ROWS 200u

// 96 bytes, made once per world (the CPU's makeJoints): a joint in its bodies' frames.
typedef struct PgsJoint {
    float4 anchorA, anchorB; // the anchor in each body's frame, m
    float4 axisA;            // hinge axis in a's frame, unit
    float4 perpB[2];         // unit, perpendicular to the axis, in b's frame
    uint type;               // RUBBLE_JOINT_BALL or RUBBLE_JOINT_HINGE
    uint a, b;               // body indices
    uint pad0;
} PgsJoint;
RUBBLE_STATIC_ASSERT_SIZE(PgsJoint, 96);

// 176 bytes: a joint's rows of the current step (world frame) and its accumulated impulses,
// kept between steps for warm starting.
typedef struct PgsJointRow {
    float4 ra, rb;       // centres of mass to the anchor, m
    Mat3 pointMass;      // (J M^-1 J^T)^-1 of the point rows, kg
    float4 turn[2];      // a_1 x b_2, a_1 x c_2: the hinge rows' angular Jacobian on a
    float4 turnMass;     // (J M^-1 J^T)^-1 of the hinge rows, kg m^2: (k00, k01, k10, k11)
    float4 pointImpulse; // on b at the anchor (a gets the opposite), N s
    float4 turnImpulse;  // x, y: along turn[0], turn[1] on a (b gets the opposite), N m s
    float4 state;        // x: 1 when a body moves in this step's solve (the rows are active);
                         // y: the step the rows look across, s
} PgsJointRow;
RUBBLE_STATIC_ASSERT_SIZE(PgsJointRow, 176);

// A body as the joints see it: its inverse mass (r0.w of JacobiBody, 0 when it does not move)
// and world inverse inertia.
RUBBLE_FN float jointInverseMassItem(JacobiBody j) {
    return j.inverseInertiaWorld.r0.w;
}

// The cross-product matrix: skew(r) v = r x v.
RUBBLE_FN Mat3 skewItem(float4 r) {
    Mat3 m;
    m.r0 = vec4(0.0f, -r.z, r.y);
    m.r1 = vec4(r.z, 0.0f, -r.x);
    m.r2 = vec4(-r.y, r.x, 0.0f);
    return m;
}

RUBBLE_FN Mat3 mat3Sub(Mat3 a, Mat3 b) {
    Mat3 r;
    r.r0 = sub4(a.r0, b.r0);
    r.r1 = sub4(a.r1, b.r1);
    r.r2 = sub4(a.r2, b.r2);
    return r;
}

// Inverse of a 3x3 matrix by cofactors; zero when |det| <= 1e-12 (prepareJoints' safeInverse).
RUBBLE_FN Mat3 safeInverse3Item(Mat3 m) {
    const float c00 = m.r1.y * m.r2.z - m.r1.z * m.r2.y;
    const float c01 = m.r1.x * m.r2.z - m.r1.z * m.r2.x;
    const float c02 = m.r1.x * m.r2.y - m.r1.y * m.r2.x;
    const float det = m.r0.x * c00 - m.r0.y * c01 + m.r0.z * c02;
    Mat3 r;
    if (!(fabs(det) > 1e-12f)) {
        r.r0 = r.r1 = r.r2 = vec4(0.0f, 0.0f, 0.0f);
        return r;
    }
    const float s = 1.0f / det;
    r.r0 = vec4(c00 * s, -(m.r0.y * m.r2.z - m.r0.z * m.r2.y) * s,
                (m.r0.y * m.r1.z - m.r0.z * m.r1.y) * s);
    r.r1 = vec4(-c01 * s, (m.r0.x * m.r2.z - m.r0.z * m.r2.x) * s,
                -(m.r0.x * m.r1.z - m.r0.z * m.r1.x) * s);
    r.r2 = vec4(c02 * s, -(m.r0.x * m.r2.y - m.r0.y * m.r2.x) * s,
                (m.r0.x * m.r1.y - m.r0.y * m.r1.x) * s);
    return r;
}

// Stage buildContactRows for one joint (prepareJoints): world offsets and the effective masses
// of both blocks at the current poses; impulses zeroed without warm starting or when neither
// body moves. `row` holds last step's impulses.
RUBBLE_FN PgsJointRow prepareJointItem(PgsJoint j, PgsJointRow row, BodyPose pa, BodyPose pb,
                                       JacobiBody ja, JacobiBody jb, int warmStart, float dt) {
    PgsJointRow r = row;
    const float ima = jointInverseMassItem(ja), imb = jointInverseMassItem(jb);
    const int active = ima > 0.0f || imb > 0.0f;
    r.state = vec4(active ? 1.0f : 0.0f, dt, 0.0f);
    if (!warmStart || !active) {
        r.pointImpulse = vec4(0.0f, 0.0f, 0.0f);
        r.turnImpulse = vec4(0.0f, 0.0f, 0.0f);
    }
    if (!active) return r;
    Mat3 ia = ja.inverseInertiaWorld, ib = jb.inverseInertiaWorld;
    ia.r0.w = 0.0f;
    ib.r0.w = 0.0f;
    r.ra = quatRotate(pa.orientation, j.anchorA);
    r.rb = quatRotate(pb.orientation, j.anchorB);
    // K = (m_a^-1 + m_b^-1) 1 - [r_a] I_a^-1 [r_a] - [r_b] I_b^-1 [r_b]
    const Mat3 sa = skewItem(r.ra), sb = skewItem(r.rb);
    Mat3 k;
    k.r0 = vec4(ima + imb, 0.0f, 0.0f);
    k.r1 = vec4(0.0f, ima + imb, 0.0f);
    k.r2 = vec4(0.0f, 0.0f, ima + imb);
    k = mat3Sub(mat3Sub(k, mat3Mul(mat3Mul(sa, ia), sa)), mat3Mul(mat3Mul(sb, ib), sb));
    r.pointMass = safeInverse3Item(k);
    if (j.type == RUBBLE_JOINT_HINGE) {
        const float4 a1 = quatRotate(pa.orientation, j.axisA);
        r.turn[0] = cross3(a1, quatRotate(pb.orientation, j.perpB[0]));
        r.turn[1] = cross3(a1, quatRotate(pb.orientation, j.perpB[1]));
        Mat3 sum;
        sum.r0 = add4(ia.r0, ib.r0);
        sum.r1 = add4(ia.r1, ib.r1);
        sum.r2 = add4(ia.r2, ib.r2);
        const float k00 = dot3(r.turn[0], mat3MulVec(sum, r.turn[0]));
        const float k01 = dot3(r.turn[0], mat3MulVec(sum, r.turn[1]));
        const float k11 = dot3(r.turn[1], mat3MulVec(sum, r.turn[1]));
        // The inverse as the CPU's glm::inverse rounds it: times the determinant's reciprocal.
        const float det = k00 * k11 - k01 * k01;
        const float s = 1.0f / det;
        r.turnMass = fabs(det) > 1e-12f ? make4(k11 * s, -k01 * s, -k01 * s, k00 * s)
                                        : make4(0.0f, 0.0f, 0.0f, 0.0f);
    }
    return r;
}

// The point block's impulse (on b, a gets the opposite) applied to both velocities.
RUBBLE_FN BodyVelocityPair applyJointPointItem(BodyVelocityPair v, PgsJointRow r, float4 impulse,
                                               JacobiBody ja, JacobiBody jb) {
    v.a.linear = sub4(v.a.linear, scale4(impulse, jointInverseMassItem(ja)));
    v.a.angular = sub4(v.a.angular, mat3MulVec(ja.inverseInertiaWorld, cross3(r.ra, impulse)));
    v.b.linear = add4(v.b.linear, scale4(impulse, jointInverseMassItem(jb)));
    v.b.angular = add4(v.b.angular, mat3MulVec(jb.inverseInertiaWorld, cross3(r.rb, impulse)));
    return v;
}

// The hinge block's impulse (x, y along turn[0], turn[1] on a; b gets the opposite).
RUBBLE_FN BodyVelocityPair applyJointTurnItem(BodyVelocityPair v, PgsJointRow r, float4 impulse,
                                              JacobiBody ja, JacobiBody jb) {
    const float4 torque = add4(scale4(r.turn[0], impulse.x), scale4(r.turn[1], impulse.y));
    v.a.angular = add4(v.a.angular, mat3MulVec(ja.inverseInertiaWorld, torque));
    v.b.angular = sub4(v.b.angular, mat3MulVec(jb.inverseInertiaWorld, torque));
    return v;
}

// Warm start: the accumulated impulses applied (warmStartJoints).
RUBBLE_FN BodyVelocityPair warmStartJointItem(BodyVelocityPair v, PgsJoint j, PgsJointRow r,
                                              JacobiBody ja, JacobiBody jb) {
    if (r.state.x == 0.0f) return v;
    v = applyJointPointItem(v, r, r.pointImpulse, ja, jb);
    if (j.type == RUBBLE_JOINT_HINGE) v = applyJointTurnItem(v, r, r.turnImpulse, ja, jb);
    return v;
}

// A point at r from a centre turning at w leaves its straight-line path over a step of dt by
// (w dt) x ((w dt) x r) / 2 to second order (the step turns r exactly, the rows see only w x r):
// the speed that cancels it is minus this, (dt / 2) w x (w x r). Turns above half a radian a step
// get none (the series no longer holds, and such a link is flung, not swung).
RUBBLE_FN float4 turnSpeedItem(float4 w, float4 r, float dt) {
    if (dot3(w, w) * dt * dt > 0.25f) return vec4(0.0f, 0.0f, 0.0f);
    return scale4(cross3(w, cross3(w, r)), 0.5f * dt);
}

// 96 bytes, not stored: a joint's velocity update: the velocities, the joint's accumulated
// impulses, and the largest |change| (N s) in w of pointImpulse.
typedef struct PgsJointUpdate {
    BodyVelocityPair v;
    float4 pointImpulse;
    float4 turnImpulse;
} PgsJointUpdate;

// One Gauss-Seidel update of a joint's blocks toward C' = 0 (the point block toward the speed
// that cancels the anchors' parting over the step), the change scaled by relaxation
// (solveJointVelocity): the hinge block first, then the point block.
RUBBLE_FN PgsJointUpdate solveJointItem(BodyVelocityPair v, PgsJoint j, PgsJointRow r,
                                        JacobiBody ja, JacobiBody jb, float relaxation) {
    PgsJointUpdate u;
    u.v = v;
    u.pointImpulse = r.pointImpulse;
    u.turnImpulse = r.turnImpulse;
    if (r.state.x == 0.0f) {
        u.pointImpulse.w = 0.0f;
        return u;
    }
    float residual = 0.0f;
    if (j.type == RUBBLE_JOINT_HINGE) {
        const float4 dw = sub4(u.v.a.angular, u.v.b.angular);
        const float s0 = dot3(r.turn[0], dw), s1 = dot3(r.turn[1], dw);
        const float4 m = r.turnMass;
        const float4 impulse =
            vec4(-(m.x * s0 + m.y * s1) * relaxation, -(m.z * s0 + m.w * s1) * relaxation, 0.0f);
        u.turnImpulse = add4(u.turnImpulse, impulse);
        u.v = applyJointTurnItem(u.v, r, impulse, ja, jb);
        residual = fmax(fabs(impulse.x), fabs(impulse.y));
    }
    // The anchors part by the turns' second-order motion over the step: the rows ask for the
    // speed that brings them back together at its end, from the velocities as they are now.
    const float4 parting = sub4(turnSpeedItem(u.v.b.angular, r.rb, r.state.y),
                                turnSpeedItem(u.v.a.angular, r.ra, r.state.y));
    const float4 speed = add4(sub4(add4(u.v.b.linear, cross3(u.v.b.angular, r.rb)),
                                   add4(u.v.a.linear, cross3(u.v.a.angular, r.ra))),
                              parting);
    const float4 impulse = scale4(mat3MulVec(r.pointMass, speed), -relaxation);
    u.pointImpulse = add4(vec4(u.pointImpulse.x, u.pointImpulse.y, u.pointImpulse.z), impulse);
    u.v = applyJointPointItem(u.v, r, impulse, ja, jb);
    residual = fmax(residual, fmax(fabs(impulse.x), fmax(fabs(impulse.y), fabs(impulse.z))));
    u.pointImpulse.w = residual;
    return u;
}

// 16 bytes: a joint group projected as one on the device: its joints are members[first ..
// first + count), its rows and its matrix use the scratch from rowStart and matrixStart.
typedef struct JointGroup {
    uint first, count;
    uint rowStart, matrixStart;
} JointGroup;
RUBBLE_STATIC_ASSERT_SIZE(JointGroup, 16);

#define RUBBLE_JOINT_ROW_POINT 1u
#define RUBBLE_JOINT_ROW_MOVES_A 2u
#define RUBBLE_JOINT_ROW_MOVES_B 4u

// 144 bytes (scratch): one constraint row of a group's projection at the current poses: C, its
// Jacobian on each body and M^-1 J^T (joint_positions.cpp's PositionRow).
typedef struct JointPositionRow {
    float4 linearA, angularA, linearB, angularB;
    float4 moveA, turnA, moveB, turnB;
    float error; // m for point rows, the cosine for hinge rows
    uint a, b;
    uint
        kind; // RUBBLE_JOINT_ROW_POINT for a point row (else a hinge row), RUBBLE_JOINT_ROW_MOVES_*
} JointPositionRow;
RUBBLE_STATIC_ASSERT_SIZE(JointPositionRow, 144);

// A body as the projection sees it at `pose`: its inverse mass and world inverse inertia, zero
// when it does not move (the CPU's inverseOf).
RUBBLE_FN JacobiBody projectionBodyItem(BodyMass m, uint flags, BodyPose pose) {
    if (!activeBodyItem(flags) || !(m.inverseMass > 0.0f)) m = wallMassItem(m);
    return jacobiBodyItem(m, pose.orientation);
}

// 8 bytes, not stored: the largest |C| of a set of joint rows, of the point rows (m) and of the
// hinge rows.
typedef struct JointErrors {
    float linear, angular;
} JointErrors;

RUBBLE_FN JointErrors noJointErrorsItem(void) {
    JointErrors e;
    e.linear = 0.0f;
    e.angular = 0.0f;
    return e;
}

// Whether rows with these largest errors are within the projection's tolerances.
RUBBLE_FN int jointErrorsWithinItem(JointErrors e) {
    return e.linear <= RUBBLE_JOINT_LINEAR_TOLERANCE && e.angular <= RUBBLE_JOINT_ANGULAR_TOLERANCE;
}

// One joint's rows at the current poses into out[0..): three point rows along the world axes,
// and for a hinge the two rows a_1 . b_2, a_1 . c_2; their errors go into *errors. Returns the
// row count (0 when neither body moves).
RUBBLE_FN uint jointRowsItem(PgsJoint j, BodyPose pa, BodyPose pb, JacobiBody ja, JacobiBody jb,
                             JointPositionRow* out, JointErrors* errors) {
    const float ima = jointInverseMassItem(ja), imb = jointInverseMassItem(jb);
    if (ima == 0.0f && imb == 0.0f) return 0u;
    Mat3 ia = ja.inverseInertiaWorld, ib = jb.inverseInertiaWorld;
    ia.r0.w = 0.0f;
    ib.r0.w = 0.0f;
    const float4 ra = quatRotate(pa.orientation, j.anchorA);
    const float4 rb = quatRotate(pb.orientation, j.anchorB);
    float4 c = sub4(add4(pb.position, rb), add4(pa.position, ra));
    c = vec4(c.x, c.y, c.z);
    const float size = length3(c);
    if (size > RUBBLE_JOINT_MAX_LINEAR_CORRECTION)
        c = scale4(c, RUBBLE_JOINT_MAX_LINEAR_CORRECTION / size);
    const float cs[3] = {c.x, c.y, c.z};
    const float4 a1 = quatRotate(pa.orientation, j.axisA);
    const uint total = j.type == RUBBLE_JOINT_HINGE ? 5u : 3u;
    for (uint k = 0; k < total; ++k) {
        JointPositionRow r;
        if (k < 3u) {
            // C_k = (p_b - p_a) . e_k: turning a by theta moves p_a by theta x r_a.
            const float4 e =
                vec4(k == 0u ? 1.0f : 0.0f, k == 1u ? 1.0f : 0.0f, k == 2u ? 1.0f : 0.0f);
            r.linearA = scale4(e, -1.0f);
            r.angularA = scale4(cross3(ra, e), -1.0f);
            r.linearB = e;
            r.angularB = cross3(rb, e);
            r.error = cs[k];
            r.kind = RUBBLE_JOINT_ROW_POINT;
        } else {
            // d(a_1 . p_2) = (theta_a - theta_b) . (a_1 x p_2)
            const float4 p2 = quatRotate(pb.orientation, j.perpB[k - 3u]);
            const float4 turn = cross3(a1, p2);
            r.linearA = vec4(0.0f, 0.0f, 0.0f);
            r.angularA = turn;
            r.linearB = vec4(0.0f, 0.0f, 0.0f);
            r.angularB = scale4(turn, -1.0f);
            r.error = dot3(a1, p2);
            r.kind = 0u;
        }
        r.moveA = scale4(r.linearA, ima);
        r.turnA = mat3MulVec(ia, r.angularA);
        r.moveB = scale4(r.linearB, imb);
        r.turnB = mat3MulVec(ib, r.angularB);
        r.a = j.a;
        r.b = j.b;
        if (r.kind & RUBBLE_JOINT_ROW_POINT)
            errors->linear = fmax(errors->linear, fabs(r.error));
        else
            errors->angular = fmax(errors->angular, fabs(r.error));
        r.kind |= (ima > 0.0f ? RUBBLE_JOINT_ROW_MOVES_A : 0u) |
                  (imb > 0.0f ? RUBBLE_JOINT_ROW_MOVES_B : 0u);
        out[k] = r;
    }
    return total;
}

// Appends one joint's rows at the current poses to rows[n..] (jointRowsItem), their errors into
// *errors. Returns the new row count.
RUBBLE_FN uint appendJointRowsItem(PgsJoint j, BodyPose pa, BodyPose pb, JacobiBody ja,
                                   JacobiBody jb, RUBBLE_GLOBAL JointPositionRow* rows, uint n,
                                   JointErrors* errors) {
    JointPositionRow own[5];
    const uint count = jointRowsItem(j, pa, pb, ja, jb, own, errors);
    for (uint k = 0; k < count; ++k) rows[n + k] = own[k];
    return n + count;
}

// J_x M^-1 J_y^T over the bodies two rows share: each body's two dot products in float, their
// sum added to the total in JointReal, as the CPU's coupling adds glm::dot's floats in double.
RUBBLE_FN JointReal jointRowCouplingItem(JointPositionRow x, JointPositionRow y) {
    JointReal k = 0.0f;
    if (x.a == y.a) k += dot3(x.linearA, y.moveA) + dot3(x.angularA, y.turnA);
    if (x.a == y.b) k += dot3(x.linearA, y.moveB) + dot3(x.angularA, y.turnB);
    if (x.b == y.a) k += dot3(x.linearB, y.moveA) + dot3(x.angularB, y.turnA);
    if (x.b == y.b) k += dot3(x.linearB, y.moveB) + dot3(x.angularB, y.turnB);
    return k;
}

// 64 bytes, not stored: the two poses after a joint's projection, and whether it moved them
// (w of a.position: 1 when it did).
typedef struct PosePair {
    BodyPose a, b;
} PosePair;

// One Newton step of a single joint onto its constraints at the current poses
// (joint_positions.cpp, projectOnce for one joint): the 3 point rows (and the 2 hinge rows)
// C = 0 solved by LDL^T for lambda = -(J M^-1 J^T)^-1 C, the bodies moved by M^-1 J^T lambda
// with the turn limited to RUBBLE_JOINT_MAX_ANGULAR_CORRECTION. ia, ib are the bodies' inverse
// masses and world inverse inertias at these poses (zero for one that does not move). moved is
// set to 0 when the joint is within tolerance (nothing moves).
RUBBLE_FN PosePair projectJointItem(PgsJoint j, BodyPose pa, BodyPose pb, JacobiBody ja,
                                    JacobiBody jb, int* moved) {
    PosePair out;
    out.a = pa;
    out.b = pb;
    *moved = 0;
    // Rows: J on a (linear, angular) and on b, M^-1 J^T, and the error C.
    JointPositionRow rows[5];
    JointErrors errors = noJointErrorsItem();
    const int n = (int)jointRowsItem(j, pa, pb, ja, jb, rows, &errors);
    if (n == 0 || jointErrorsWithinItem(errors)) return out;
    // K = J M^-1 J^T (lower triangle), right-hand side -C.
    JointReal k[25], x[5];
    JointReal largest = 0.0f;
    for (int i = 0; i < n; ++i) {
        const JointPositionRow ri = rows[i];
        for (int q = 0; q <= i; ++q) k[i * 5 + q] = jointRowCouplingItem(ri, rows[q]);
        largest = fmax(largest, k[i * 5 + i]);
        x[i] = -(JointReal)ri.error;
    }
    // LDL^T: L below the diagonal, D on it; a zero D marks a dropped row.
    for (int q = 0; q < n; ++q) {
        JointReal d = k[q * 5 + q];
        for (int p = 0; p < q; ++p) d -= k[q * 5 + p] * k[q * 5 + p] * k[p * 5 + p];
        if (d <= RUBBLE_JOINT_PIVOT_TOLERANCE * largest) d = 0.0f;
        k[q * 5 + q] = d;
        for (int i = q + 1; i < n; ++i) {
            JointReal l = k[i * 5 + q];
            for (int p = 0; p < q; ++p) l -= k[i * 5 + p] * k[q * 5 + p] * k[p * 5 + p];
            k[i * 5 + q] = d > 0.0f ? l / d : (JointReal)0.0f;
        }
    }
    for (int i = 0; i < n; ++i)
        for (int p = 0; p < i; ++p) x[i] -= k[i * 5 + p] * x[p];
    for (int i = 0; i < n; ++i) x[i] = k[i * 5 + i] > 0.0f ? x[i] / k[i * 5 + i] : (JointReal)0.0f;
    for (int i = n - 1; i >= 0; --i)
        for (int p = i + 1; p < n; ++p) x[i] -= k[p * 5 + i] * x[p];
    // The move, a turn past the limit shortened as a whole.
    float4 dxA = vec4(0.0f, 0.0f, 0.0f), dqA = dxA, dxB = dxA, dqB = dxA;
    for (int i = 0; i < n; ++i) {
        const float lambda = (float)x[i];
        dxA = add4(dxA, scale4(rows[i].moveA, lambda));
        dqA = add4(dqA, scale4(rows[i].turnA, lambda));
        dxB = add4(dxB, scale4(rows[i].moveB, lambda));
        dqB = add4(dqB, scale4(rows[i].turnB, lambda));
    }
    const float largestTurn = fmax(length3(dqA), length3(dqB));
    const float scale = largestTurn > RUBBLE_JOINT_MAX_ANGULAR_CORRECTION
                            ? RUBBLE_JOINT_MAX_ANGULAR_CORRECTION / largestTurn
                            : 1.0f;
    *moved = 1;
    if (rows[0].kind & RUBBLE_JOINT_ROW_MOVES_A) {
        out.a.position = add4(pa.position, scale4(dxA, scale));
        out.a.orientation = quatIntegrate(pa.orientation, scale4(dqA, scale), 1.0f);
    }
    if (rows[0].kind & RUBBLE_JOINT_ROW_MOVES_B) {
        out.b.position = add4(pb.position, scale4(dxB, scale));
        out.b.orientation = quatIntegrate(pb.orientation, scale4(dqB, scale), 1.0f);
    }
    return out;
}

// The CPU path's position correction of one joint group (correctJointPositions on a group of at
// most RUBBLE_JOINT_DIRECT_ROWS rows): up to `maxIterations` Newton steps, each with every
// row of the group at the current poses, K lambda = -C solved by LDL^T (redundant rows get no
// impulse), the bodies moved by M^-1 J^T lambda with the turn limited as a whole; it stops once
// every joint is within tolerance. Only awake dynamic bodies move. rows, k (n x n, row-major)
// and x are the group's scratch; deltaPosition and deltaRotation are per body, zero between
// uses. Returns the Newton steps taken.
RUBBLE_FN int projectJointGroupItem(RUBBLE_GLOBAL const uint* members, uint count,
                                    RUBBLE_GLOBAL const PgsJoint* joints,
                                    RUBBLE_GLOBAL const BodyMass* masses,
                                    RUBBLE_GLOBAL const uint* flags, RUBBLE_GLOBAL BodyPose* poses,
                                    RUBBLE_GLOBAL JointPositionRow* rows,
                                    RUBBLE_GLOBAL JointReal* k, RUBBLE_GLOBAL JointReal* x,
                                    RUBBLE_GLOBAL float4* deltaPosition,
                                    RUBBLE_GLOBAL float4* deltaRotation, int maxIterations) {
    int it = 0;
    for (; it < maxIterations; ++it) {
        uint n = 0;
        JointErrors errors = noJointErrorsItem();
        for (uint m = 0; m < count; ++m) {
            const PgsJoint j = joints[members[m]];
            const BodyPose pa = poses[j.a], pb = poses[j.b];
            n = appendJointRowsItem(j, pa, pb, projectionBodyItem(masses[j.a], flags[j.a], pa),
                                    projectionBodyItem(masses[j.b], flags[j.b], pb), rows, n,
                                    &errors);
        }
        if (jointErrorsWithinItem(errors)) break;
        // K (lower triangle) and -C.
        JointReal largest = 0.0f;
        for (uint i = 0; i < n; ++i) {
            const JointPositionRow ri = rows[i];
            for (uint q = 0; q <= i; ++q) k[i * n + q] = jointRowCouplingItem(ri, rows[q]);
            largest = fmax(largest, k[i * n + i]);
            x[i] = -(JointReal)ri.error;
        }
        // LDL^T: L below the diagonal, D on it; a zero D marks a dropped row.
        for (uint q = 0; q < n; ++q) {
            JointReal d = k[q * n + q];
            for (uint p = 0; p < q; ++p) d -= k[q * n + p] * k[q * n + p] * k[p * n + p];
            if (d <= RUBBLE_JOINT_PIVOT_TOLERANCE * largest) d = 0.0f;
            k[q * n + q] = d;
            for (uint i = q + 1; i < n; ++i) {
                JointReal l = k[i * n + q];
                for (uint p = 0; p < q; ++p) l -= k[i * n + p] * k[q * n + p] * k[p * n + p];
                k[i * n + q] = d > 0.0f ? l / d : (JointReal)0.0f;
            }
        }
        for (uint i = 0; i < n; ++i)
            for (uint p = 0; p < i; ++p) x[i] -= k[i * n + p] * x[p];
        for (uint i = 0; i < n; ++i)
            x[i] = k[i * n + i] > 0.0f ? x[i] / k[i * n + i] : (JointReal)0.0f;
        for (uint i = n; i-- > 0u;)
            for (uint p = i + 1; p < n; ++p) x[i] -= k[p * n + i] * x[p];
        // The move of each body that moves (a static body may be shared with other groups), a
        // turn past the limit shortening the whole step.
        float largestTurn = 0.0f;
        for (uint i = 0; i < n; ++i) {
            const JointPositionRow r = rows[i];
            const float lambda = (float)x[i];
            if (r.kind & RUBBLE_JOINT_ROW_MOVES_A) {
                deltaPosition[r.a] = add4(deltaPosition[r.a], scale4(r.moveA, lambda));
                deltaRotation[r.a] = add4(deltaRotation[r.a], scale4(r.turnA, lambda));
            }
            if (r.kind & RUBBLE_JOINT_ROW_MOVES_B) {
                deltaPosition[r.b] = add4(deltaPosition[r.b], scale4(r.moveB, lambda));
                deltaRotation[r.b] = add4(deltaRotation[r.b], scale4(r.turnB, lambda));
            }
        }
        for (uint i = 0; i < n; ++i) {
            if (rows[i].kind & RUBBLE_JOINT_ROW_MOVES_A)
                largestTurn = fmax(largestTurn, length3(deltaRotation[rows[i].a]));
            if (rows[i].kind & RUBBLE_JOINT_ROW_MOVES_B)
                largestTurn = fmax(largestTurn, length3(deltaRotation[rows[i].b]));
        }
        const float scale = largestTurn > RUBBLE_JOINT_MAX_ANGULAR_CORRECTION
                                ? RUBBLE_JOINT_MAX_ANGULAR_CORRECTION / largestTurn
                                : 1.0f;
        const float4 zero = vec4(0.0f, 0.0f, 0.0f);
        for (uint i = 0; i < n; ++i) {
            for (uint side = 0; side < 2u; ++side) {
                const uint moves = side ? RUBBLE_JOINT_ROW_MOVES_B : RUBBLE_JOINT_ROW_MOVES_A;
                if (!(rows[i].kind & moves)) continue;
                const uint body = side ? rows[i].b : rows[i].a;
                const float4 dx = scale4(deltaPosition[body], scale);
                const float4 dq = scale4(deltaRotation[body], scale);
                if (dx.x == 0.0f && dx.y == 0.0f && dx.z == 0.0f && dq.x == 0.0f && dq.y == 0.0f &&
                    dq.z == 0.0f)
                    continue;
                BodyPose pose = poses[body];
                pose.position = add4(pose.position, dx);
                pose.orientation = quatIntegrate(pose.orientation, dq, 1.0f);
                poses[body] = pose;
                deltaPosition[body] = zero;
                deltaRotation[body] = zero;
            }
        }
    }
    return it;
}

RUBBLE_SHARED_END
