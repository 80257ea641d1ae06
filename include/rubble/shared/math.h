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
// The half angles (rad) up to which quatExp sums the series directly; larger ones are halved
// first and the result squared back. Past 0.5 rad the series' error stays below 1e-9.
#define RUBBLE_SERIES_HALF_ANGLE 0.5f
#define RUBBLE_MAX_SQUARINGS 24

// exp((v, 0)) = (sin|v| v/|v|, cos|v|): the unit quaternion that turns by 2|v| about v. sin(x)/x
// and cos(x) by their Taylor series to x^8, in the same operations on the host and in the
// kernels (the device's sin and cos may differ from the host's in the last bit, and a tumbling
// body grows that to 1e-4 within 200 steps); a half angle above RUBBLE_SERIES_HALF_ANGLE is
// halved k times and the quaternion squared k times (exp(2u) = exp(u)^2).
RUBBLE_FN float4 quatExp(float4 v) {
    float x = length3(v), scale = 1.0f;
    int squarings = 0;
    while (x > RUBBLE_SERIES_HALF_ANGLE && squarings < RUBBLE_MAX_SQUARINGS) {
        x *= 0.5f;
        scale *= 0.5f;
        ++squarings;
    }
    const float x2 = x * x;
    const float sinc =
        1.0f - x2 / 6.0f * (1.0f - x2 / 20.0f * (1.0f - x2 / 42.0f * (1.0f - x2 / 72.0f)));
    const float c =
        1.0f - x2 / 2.0f * (1.0f - x2 / 12.0f * (1.0f - x2 / 30.0f * (1.0f - x2 / 56.0f)));
    const float k = scale * sinc;
    float4 q = make4(v.x * k, v.y * k, v.z * k, c);
    for (int i = 0; i < squarings; ++i) q = quatMul(q, q);
    return q;
}

// dq/dt = 1/2 (omega, 0) q over dt for a constant omega (world frame, rad/s), solved exactly: q
// turned by the angle |omega| dt about omega (the exponential map), renormalised against
// round-off. The first-order step normalise(q + dt/2 (omega, 0) q) turns by 2 atan(|omega| dt /
// 2) instead: 0.23% short at 10 rad/s and 60 Hz.
RUBBLE_FN float4 quatIntegrate(float4 q, float4 omega, float dt) {
    const float4 halfTurn = scale4(vec4(omega.x, omega.y, omega.z), 0.5f * dt);
    return quatNormalize(quatMul(quatExp(halfTurn), q));
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
