// include/rubble/shared/math.h: vector, quaternion and 3x3 math on float4, for host and kernels.
// Vectors use x, y, z (w = 0); quaternions are (x, y, z, w) with w the scalar part.
#pragma once

#include "rubble/shared/cl_compat.h"

RUBBLE_SHARED_BEGIN

// 48 bytes: a 3x3 matrix as three rows (w of each row = 0).
typedef struct Mat3 {
    float4 r0, r1, r2;
} Mat3;
RUBBLE_STATIC_ASSERT_SIZE(Mat3, 48);

RUBBLE_FN float4 make4(float x, float y, float z, float w) {
    float4 r;
    r.x = x;
    r.y = y;
    r.z = z;
    r.w = w;
    return r;
}
RUBBLE_FN float4 vec4(float x, float y, float z) { return make4(x, y, z, 0.0f); }
RUBBLE_FN float4 add4(float4 a, float4 b) { return make4(a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w); }
RUBBLE_FN float4 sub4(float4 a, float4 b) { return make4(a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w); }
RUBBLE_FN float4 scale4(float4 a, float s) { return make4(a.x * s, a.y * s, a.z * s, a.w * s); }
RUBBLE_FN float4 mul4(float4 a, float4 b) { return make4(a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w); }
RUBBLE_FN float dot3(float4 a, float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
RUBBLE_FN float4 cross3(float4 a, float4 b) {
    return vec4(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
RUBBLE_FN float length3(float4 a) { return sqrt(dot3(a, a)); }
RUBBLE_FN float4 normalize3(float4 a) {
    const float len = length3(a);
    return len > 0.0f ? scale4(a, 1.0f / len) : a;
}

// Hamilton product a b: rotating by b, then by a.
RUBBLE_FN float4 quatMul(float4 a, float4 b) {
    return make4(a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                 a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                 a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                 a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
}
RUBBLE_FN float4 quatConj(float4 q) { return make4(-q.x, -q.y, -q.z, q.w); }
RUBBLE_FN float4 quatNormalize(float4 q) {
    const float len = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return len > 0.0f ? scale4(q, 1.0f / len) : make4(0.0f, 0.0f, 0.0f, 1.0f);
}
// q v q^-1 for a unit quaternion, as v + 2 w (u x v) + 2 u x (u x v) with u the vector part.
RUBBLE_FN float4 quatRotate(float4 q, float4 v) {
    const float4 u = vec4(q.x, q.y, q.z);
    const float4 t = scale4(cross3(u, v), 2.0f);
    return add4(add4(vec4(v.x, v.y, v.z), scale4(t, q.w)), cross3(u, t));
}
// q^-1 v q: a world vector in the body frame.
RUBBLE_FN float4 quatRotateInverse(float4 q, float4 v) { return quatRotate(quatConj(q), v); }
// One explicit step of dq/dt = 1/2 (omega, 0) q, then renormalised (Baraff 1997, eq. 4-4).
RUBBLE_FN float4 quatIntegrate(float4 q, float4 omega, float dt) {
    const float4 w = vec4(omega.x, omega.y, omega.z);
    return quatNormalize(add4(q, scale4(quatMul(w, q), 0.5f * dt)));
}

RUBBLE_FN float4 mat3MulVec(Mat3 m, float4 v) { return vec4(dot3(m.r0, v), dot3(m.r1, v), dot3(m.r2, v)); }
RUBBLE_FN Mat3 mat3Transpose(Mat3 m) {
    Mat3 t;
    t.r0 = vec4(m.r0.x, m.r1.x, m.r2.x);
    t.r1 = vec4(m.r0.y, m.r1.y, m.r2.y);
    t.r2 = vec4(m.r0.z, m.r1.z, m.r2.z);
    return t;
}
RUBBLE_FN Mat3 mat3Mul(Mat3 a, Mat3 b) {
    const Mat3 bt = mat3Transpose(b);
    Mat3 r;
    r.r0 = vec4(dot3(a.r0, bt.r0), dot3(a.r0, bt.r1), dot3(a.r0, bt.r2));
    r.r1 = vec4(dot3(a.r1, bt.r0), dot3(a.r1, bt.r1), dot3(a.r1, bt.r2));
    r.r2 = vec4(dot3(a.r2, bt.r0), dot3(a.r2, bt.r1), dot3(a.r2, bt.r2));
    return r;
}
// The rotation matrix of a unit quaternion.
RUBBLE_FN Mat3 mat3FromQuat(float4 q) {
    const float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    const float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    Mat3 m;
    m.r0 = vec4(1.0f - 2.0f * (yy + zz), 2.0f * (xy - wz), 2.0f * (xz + wy));
    m.r1 = vec4(2.0f * (xy + wz), 1.0f - 2.0f * (xx + zz), 2.0f * (yz - wx));
    m.r2 = vec4(2.0f * (xz - wy), 2.0f * (yz + wx), 1.0f - 2.0f * (xx + yy));
    return m;
}
// R A R^T: a body-frame tensor in the world frame.
RUBBLE_FN Mat3 mat3RotateTensor(Mat3 r, Mat3 a) { return mat3Mul(mat3Mul(r, a), mat3Transpose(r)); }

RUBBLE_SHARED_END
