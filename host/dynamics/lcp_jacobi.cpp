// host/dynamics/lcp_jacobi.cpp: the dense contact problem on the CPU, projected Jacobi on it
// (twin of kernels/lcp_jacobi.cl), and the lcp-jacobi and lemke solve stages of a world.
#include "host/dynamics/lcp_jacobi.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "host/core/assert.h"
#include "host/dynamics/jacobi.h"
#include "host/dynamics/lemke.h"

namespace rubble {

using namespace shared;

std::uint32_t lcpStrideOfRows(std::span<const shared::ContactRow> rows) {
    for (const shared::ContactRow& r : rows)
        if (r.friction > 0.0f) return 3u;
    return 1u;
}

namespace {

// A sleeping body takes part as a wall, as in buildJacobiRows.
BodyMass rowMassOf(const BodyMass& m) {
    return (m.flags & RUBBLE_BODY_ASLEEP) ? wallMassItem(m) : m;
}

} // namespace

void buildLcpRows(std::span<const shared::ContactRow> rows, std::span<const BodyVelocity> velocities,
                  std::span<const BodyMass> masses, std::span<const BodyPose> poses,
                  std::uint32_t stride, DenseLcp& p) {
    RUBBLE_ASSERT(stride == 1u || stride == 3u);
    p.contacts = std::uint32_t(rows.size());
    p.stride = stride;
    const std::size_t n = p.size();
    p.rows.resize(n);
    p.rhs.resize(n);
    p.lambda.resize(n);
    p.friction.resize(p.contacts);
    for (std::uint32_t c = 0; c < p.contacts; ++c) {
        const shared::ContactRow& r = rows[c];
        const BodyMass ma = rowMassOf(masses[r.a]), mb = rowMassOf(masses[r.b]);
        const Mat3 invIA = inverseInertiaWorldItem(ma, poses[r.a].orientation);
        const Mat3 invIB = inverseInertiaWorldItem(mb, poses[r.b].orientation);
        const float warm[3] = {r.lambda.x, r.lambda.y, r.lambda.z};
        for (std::uint32_t k = 0; k < stride; ++k) {
            const std::size_t i = std::size_t(c) * stride + k;
            p.rows[i] = lcpRowItem(r, k, ma, invIA, mb, invIB);
            p.rhs[i] = lcpRhsItem(r, k, velocities[r.a], velocities[r.b]);
            p.lambda[i] = warm[k];
        }
        p.friction[c] = r.friction;
    }
}

void assembleDelassus(DenseLcp& p) {
    const std::size_t n = p.size();
    p.matrix.resize(n * n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            p.matrix[i * n + j] = delassusEntryItem(p.rows[i], p.rows[j]);
}

void scaleLcpRows(DenseLcp& p) {
    const std::size_t n = p.size();
    p.inverseScale.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        float sum = 0.0f;
        for (std::size_t j = 0; j < n; ++j) sum += std::fabs(p.matrix[i * n + j]);
        p.inverseScale[i] = sum > 0.0f ? 1.0f / sum : 0.0f;
    }
}

namespace {

// A contact's (up to) three entries of an array as a float4.
float4 gather3(const std::vector<float>& v, std::size_t first, std::uint32_t stride) {
    return stride == 1u ? vec4(v[first], 0.0f, 0.0f)
                        : vec4(v[first], v[first + 1], v[first + 2]);
}

} // namespace

void solveLcpJacobi(DenseLcp& p, int iterations, float relaxation) {
    const std::size_t n = p.size();
    p.product.resize(n);
    p.residuals.clear();
    std::vector<float> w(n);
    for (int k = 0; k < iterations; ++k) {
        for (std::size_t i = 0; i < n; ++i) {
            float sum = 0.0f;
            for (std::size_t j = 0; j < n; ++j) sum += p.matrix[i * n + j] * p.lambda[j];
            p.product[i] = sum;
        }
        for (std::size_t i = 0; i < n; ++i) w[i] = p.product[i] + p.rhs[i];
        float change = 0.0f;
        for (std::uint32_t c = 0; c < p.contacts; ++c) {
            const std::size_t first = std::size_t(c) * p.stride;
            const float4 before = gather3(p.lambda, first, p.stride);
            const float4 next =
                projectLcpItem(before, gather3(w, first, p.stride),
                               gather3(p.inverseScale, first, p.stride), p.friction[c],
                               relaxation, p.stride);
            change = std::max(change, impulseChangeItem(before, next));
            const float out[3] = {next.x, next.y, next.z};
            for (std::uint32_t d = 0; d < p.stride; ++d) p.lambda[first + d] = out[d];
        }
        p.residuals.push_back(change);
    }
}

void storeLcpImpulses(const DenseLcp& p, std::span<shared::ContactRow> rows) {
    RUBBLE_ASSERT(rows.size() == p.contacts);
    for (std::uint32_t c = 0; c < p.contacts; ++c)
        rows[c].lambda = gather3(p.lambda, std::size_t(c) * p.stride, p.stride);
}

void lcpNormalProblem(const DenseLcp& p, std::vector<double>& m, std::vector<double>& q) {
    RUBBLE_ASSERT(p.stride == 1u);
    const std::size_t n = p.size();
    m.assign(p.matrix.begin(), p.matrix.end());
    q.assign(p.rhs.begin(), p.rhs.end());
    RUBBLE_ASSERT(m.size() == n * n);
}

} // namespace rubble
