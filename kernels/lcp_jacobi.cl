// kernels/lcp_jacobi.cl: entry points of OpenCL stage 5, dense variant (lcp-jacobi): the dense
// rows, the Delassus matrix, the row scales, the projection after CLBlast's A lambda, and the
// impulses back into the contact rows. The math is in rubble/shared/lcp.h; the CPU twins in
// host/dynamics/lcp_jacobi.cpp.
#include "rubble/shared/lcp.h"

// One work-item per contact: its `stride` dense rows, their b, and lambda from the row's
// (warm-start) impulses. A sleeping body takes part as a wall, as in buildJacobiRows.
__kernel void buildLcpRows(const uint count, const uint stride,
                           __global const ContactRow* rows,
                           __global const BodyVelocity* velocities,
                           __global const BodyMass* masses, __global const uint* flags,
                           __global const BodyPose* poses, __global LcpRow* lcpRows,
                           __global float* rhs, __global float* lambda,
                           __global float* friction) {
    const uint c = get_global_id(0);
    if (c >= count) return;
    const ContactRow r = rows[c];
    BodyMass ma = masses[r.a], mb = masses[r.b];
    if (flags[r.a] & RUBBLE_BODY_ASLEEP) ma = wallMassItem(ma);
    if (flags[r.b] & RUBBLE_BODY_ASLEEP) mb = wallMassItem(mb);
    const Mat3 invIA = inverseInertiaWorldItem(ma, poses[r.a].orientation);
    const Mat3 invIB = inverseInertiaWorldItem(mb, poses[r.b].orientation);
    const BodyVelocity va = velocities[r.a], vb = velocities[r.b];
    const float warm[3] = {r.lambda.x, r.lambda.y, r.lambda.z};
    for (uint k = 0; k < stride; ++k) {
        const uint i = c * stride + k;
        lcpRows[i] = lcpRowItem(r, k, ma, invIA, mb, invIB);
        rhs[i] = lcpRhsItem(r, k, va, vb);
        lambda[i] = warm[k];
    }
    friction[c] = r.friction;
}

// One work-item per entry of the row-major size x size matrix.
__kernel void assembleDelassus(const uint size, __global const LcpRow* lcpRows,
                               __global float* matrix) {
    const uint e = get_global_id(0);
    if (e >= size * size) return;
    const uint i = e / size, j = e - i * size;
    matrix[e] = delassusEntryItem(lcpRows[i], lcpRows[j]);
}

// One work-item per row: 1 / sum_j |A_ij|, summed in column order as on the CPU.
__kernel void scaleLcpRows(const uint size, __global const float* matrix,
                           __global float* inverseScale) {
    const uint i = get_global_id(0);
    if (i >= size) return;
    float sum = 0.0f;
    for (uint j = 0; j < size; ++j) sum += fabs(matrix[i * size + j]);
    inverseScale[i] = sum > 0.0f ? 1.0f / sum : 0.0f;
}

// A contact's (up to) three entries of an array.
float4 loadContactRows(__global const float* v, uint first, uint stride) {
    return stride == 1u ? vec4(v[first], 0.0f, 0.0f)
                        : vec4(v[first], v[first + 1u], v[first + 2u]);
}

// One work-item per contact, after product = A lambda: the projected update from w = product
// + b. On the last sweep, the largest change goes to the status buffer as the residual.
__kernel void projectLcp(const uint count, const uint stride, __global const float* product,
                         __global const float* rhs, __global const float* inverseScale,
                         __global const float* friction, const float relaxation,
                         const uint lastSweep, __global float* lambda, __global uint* status) {
    const uint c = get_global_id(0);
    if (c >= count) return;
    const uint first = c * stride;
    const float4 before = loadContactRows(lambda, first, stride);
    const float4 w = add4(loadContactRows(product, first, stride),
                          loadContactRows(rhs, first, stride));
    const float4 next = projectLcpItem(before, w, loadContactRows(inverseScale, first, stride),
                                       friction[c], relaxation, stride);
    lambda[first] = next.x;
    if (stride == 3u) {
        lambda[first + 1u] = next.y;
        lambda[first + 2u] = next.z;
    }
    if (lastSweep)
        atomic_max(&status[RUBBLE_STATUS_RESIDUAL], as_uint(impulseChangeItem(before, next)));
}

// One work-item per contact: the dense impulses into the contact row (tangents 0 for stride 1).
__kernel void storeLcpImpulses(const uint count, const uint stride,
                               __global const float* lambda, __global ContactRow* rows) {
    const uint c = get_global_id(0);
    if (c >= count) return;
    rows[c].lambda = loadContactRows(lambda, c * stride, stride);
}
