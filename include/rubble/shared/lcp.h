// include/rubble/shared/lcp.h: the dense contact problem w = A lambda + b of the lcp-jacobi
// solver (OpenCL stage 5, dense variant) and its per-element math: a row's Jacobian, an entry
// of A = J M^-1 J^T, and one projected Jacobi update of a contact. CPU twins in
// host/dynamics/lcp_jacobi.cpp; kernels in kernels/lcp_jacobi.cl.
#pragma once

#include "rubble/shared/contact_row.h"

RUBBLE_SHARED_BEGIN

// 96 bytes: one row of the dense problem, a direction d at a contact point. Its Jacobian is
// J = [-d^T, -(rA x d)^T, d^T, (rB x d)^T] over (v_a, w_a, v_b, w_b); M^-1 J^T is kept with it.
typedef struct LcpRow {
    float4 direction; // d, unit, world (w = 0)
    float4 armA;      // rA x d, m (w = a's inverse mass, 1/kg)
    float4 armB;      // rB x d, m (w = b's inverse mass, 1/kg)
    float4 turnA;     // I_a^-1 (rA x d), world, 1/(kg m) (w = 0)
    float4 turnB;     // I_b^-1 (rB x d), world, 1/(kg m) (w = 0)
    uint a, b;        // body indices
    uint pad0, pad1;  // keeps the 16-byte stride
} LcpRow;
RUBBLE_STATIC_ASSERT_SIZE(LcpRow, 96);

// Direction k of a contact row: 0 the normal, 1 and 2 the tangents.
RUBBLE_FN float4 rowDirectionItem(ContactRow r, uint k) {
    return k == 0u ? r.normal : (k == 1u ? r.tangent1 : r.tangent2);
}

// The dense row of direction k of a contact row, with each body's world inverse inertia.
RUBBLE_FN LcpRow lcpRowItem(ContactRow r, uint k, BodyMass ma, Mat3 invIA, BodyMass mb,
                            Mat3 invIB) {
    LcpRow l;
    l.direction = rowDirectionItem(r, k);
    const float4 ca = cross3(r.rA, l.direction), cb = cross3(r.rB, l.direction);
    l.armA = make4(ca.x, ca.y, ca.z, ma.inverseMass);
    l.armB = make4(cb.x, cb.y, cb.z, mb.inverseMass);
    l.turnA = mat3MulVec(invIA, ca);
    l.turnB = mat3MulVec(invIB, cb);
    l.a = r.a;
    l.b = r.b;
    l.pad0 = 0u;
    l.pad1 = 0u;
    return l;
}

// b of direction k: the relative velocity along it before the solve, plus the normal row's bias
// (the row asks for J v + bias >= 0, so b = J v0 + bias), m/s.
RUBBLE_FN float lcpRhsItem(ContactRow r, uint k, BodyVelocity va, BodyVelocity vb) {
    const float speed = dot3(relativeVelocityItem(r, va, vb), rowDirectionItem(r, k));
    return k == 0u ? speed + r.bias : speed;
}

// A_ij = J_i M^-1 J_j^T: the sum over the bodies the two rows share, each side of a row
// signed (-1 on a, +1 on b). A static body's zero inverses make its terms vanish. (m/s)/(N s)
RUBBLE_FN float delassusEntryItem(LcpRow i, LcpRow j) {
    const float dd = dot3(i.direction, j.direction);
    float s = 0.0f;
    if (i.a == j.a) s += i.armA.w * dd + dot3(i.armA, j.turnA);
    if (i.a == j.b) s -= i.armA.w * dd + dot3(i.armA, j.turnB);
    if (i.b == j.a) s -= i.armB.w * dd + dot3(i.armB, j.turnA);
    if (i.b == j.b) s += i.armB.w * dd + dot3(i.armB, j.turnB);
    return s;
}

// One projected Jacobi update of a contact's rows (x normal, y and z tangents):
// lambda <- proj(lambda - omega (A lambda + b) / D), the normal impulse >= 0 and each friction
// impulse within +-mu of the new normal impulse. `w` is A lambda + b at the contact's rows,
// `inverseScale` 1/D. With one row per contact (frictionless), y and z stay 0.
RUBBLE_FN float4 projectLcpItem(float4 lambda, float4 w, float4 inverseScale, float friction,
                                float relaxation, uint stride) {
    const float ln = fmax(lambda.x - relaxation * w.x * inverseScale.x, 0.0f);
    if (stride == 1u) return vec4(ln, 0.0f, 0.0f);
    const float limit = friction * ln;
    const float l1 = fmin(fmax(lambda.y - relaxation * w.y * inverseScale.y, -limit), limit);
    const float l2 = fmin(fmax(lambda.z - relaxation * w.z * inverseScale.z, -limit), limit);
    return vec4(ln, l1, l2);
}

RUBBLE_SHARED_END
