// host/dynamics/lcp_convergence.cpp: every CPU solver's iterates on one frozen contact set, and
// the errors of an iterate against the dense problem.
#include "host/dynamics/lcp_convergence.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "host/core/assert.h"

namespace rubble {

using namespace shared;

Result<FrozenProblem> freezeProblem(FrozenContacts set) {
    FrozenProblem p;
    p.set = std::move(set);
    const FrozenContacts& s = p.set;
    buildBodyLists(s.contacts, s.masses, p.jacobi);
    p.jacobi.warm.assign(s.contacts.size(), vec4(0.0f, 0.0f, 0.0f));
    buildJacobiRows(s.contacts, s.poses, s.velocities, s.masses, s.surfaces,
                    s.params, p.jacobi.warm, p.jacobi);
    const std::uint32_t stride = lcpStrideOfRows(p.jacobi.rows);
    const std::size_t rows = s.contacts.size() * stride;
    if (rows > kLcpMaxRows)
        return makeError(ErrorKind::NotSupported, "step " + std::to_string(s.step),
                         std::to_string(s.contacts.size()) + " contacts make " +
                             std::to_string(rows) + " dense rows; the dense problem takes at "
                             "most " + std::to_string(kLcpMaxRows) +
                             " (an earlier step, or a smaller scene)");
    buildLcpRows(p.jacobi.rows, s.velocities, s.masses, s.poses, stride, p.dense);
    assembleDelassus(p.dense);
    scaleLcpRows(p.dense);
    return p;
}

namespace {

template <class T>
IterateErrors measure(const DenseLcp& p, std::span<const T> lambda,
                      std::span<const double> referenceW) {
    const std::size_t n = p.size();
    RUBBLE_ASSERT(lambda.size() == n);
    IterateErrors e;
    double velocityError = 0.0;
    for (std::uint32_t c = 0; c < p.contacts; ++c) {
        const std::size_t first = std::size_t(c) * p.stride;
        const double normal = std::max(double(lambda[first]), 0.0);
        for (std::uint32_t d = 0; d < p.stride; ++d) {
            const std::size_t i = first + d;
            double w = p.rhs[i];
            for (std::size_t j = 0; j < n; ++j) w += double(p.matrix[i * n + j]) * double(lambda[j]);
            const double diagonal = p.matrix[i * n + i];
            if (d == 0) {
                e.complementarity += std::abs(double(lambda[i]) * w);
                if (!referenceW.empty())
                    velocityError = std::max(velocityError, std::abs(w - referenceW[c]));
            }
            if (diagonal <= 0.0) continue;
            const double trial = double(lambda[i]) - w / diagonal;
            const double limit = double(p.friction[c]) * normal;
            const double projected = d == 0 ? std::max(trial, 0.0) : std::clamp(trial, -limit, limit);
            e.residual = std::max(e.residual, std::abs(diagonal * (double(lambda[i]) - projected)));
        }
    }
    if (!referenceW.empty()) e.velocityError = velocityError;
    return e;
}

} // namespace

IterateErrors measureIterate(const DenseLcp& p, std::span<const float> lambda,
                             std::span<const double> referenceW) {
    return measure(p, lambda, referenceW);
}

IterateErrors measureIterate(const DenseLcp& p, std::span<const double> lambda,
                             std::span<const double> referenceW) {
    return measure(p, lambda, referenceW);
}

Iterates pgsIterates(const FrozenProblem& p, int iterations, float relaxation) {
    const DenseLcp& d = p.dense;
    const std::size_t n = d.size();
    std::vector<float> lambda(n, 0.0f);
    Iterates out;
    for (int k = 0; k < iterations; ++k) {
        for (std::uint32_t c = 0; c < d.contacts; ++c) {
            for (std::uint32_t r = 0; r < d.stride; ++r) {
                const std::size_t i = std::size_t(c) * d.stride + r;
                const float diagonal = d.matrix[i * n + i];
                if (diagonal <= 0.0f) continue;
                float w = d.rhs[i];
                for (std::size_t j = 0; j < n; ++j) w += d.matrix[i * n + j] * lambda[j];
                const float trial = lambda[i] - relaxation * w / diagonal;
                const float limit = d.friction[c] * lambda[std::size_t(c) * d.stride];
                lambda[i] = r == 0 ? std::max(trial, 0.0f) : std::clamp(trial, -limit, limit);
            }
        }
        out.push_back(lambda);
    }
    return out;
}

std::vector<float> denseLambda(std::span<const shared::ContactRow> rows, std::uint32_t stride) {
    std::vector<float> out(rows.size() * stride);
    for (std::size_t c = 0; c < rows.size(); ++c) {
        const float l[3] = {rows[c].lambda.x, rows[c].lambda.y, rows[c].lambda.z};
        for (std::uint32_t d = 0; d < stride; ++d) out[c * stride + d] = l[d];
    }
    return out;
}

Iterates jacobiIterates(const FrozenProblem& p, int iterations, float relaxation) {
    JacobiState j = p.jacobi;
    const FrozenContacts& s = p.set;
    std::vector<BodyVelocity> velocities = s.velocities;
    gatherJacobi(j.rows, j, s.velocities, s.masses, s.poses, velocities);
    Iterates out;
    for (int k = 0; k < iterations; ++k) {
        solveJacobiRows(j.rows, velocities, relaxation);
        gatherJacobi(j.rows, j, s.velocities, s.masses, s.poses, velocities);
        out.push_back(denseLambda(j.rows, p.dense.stride));
    }
    return out;
}

Iterates lcpJacobiIterates(const FrozenProblem& p, int iterations, float relaxation) {
    DenseLcp d = p.dense;
    std::fill(d.lambda.begin(), d.lambda.end(), 0.0f);
    Iterates out;
    for (int k = 0; k < iterations; ++k) {
        solveLcpJacobi(d, 1, relaxation);
        out.push_back(d.lambda);
    }
    return out;
}

Result<LemkeSolution> lemkeOf(const FrozenProblem& p) {
    if (p.dense.stride != 1u)
        return makeError(ErrorKind::NotSupported, "lemke",
                         "the contact set has friction; Lemke's method here solves frictionless "
                         "sets (--frictionless sets every material's friction to 0)");
    if (p.dense.size() > kLemkeMaxRows)
        return makeError(ErrorKind::NotSupported, "lemke",
                         "the contact set has " + std::to_string(p.dense.size()) +
                             " rows; Lemke's method here takes at most " +
                             std::to_string(kLemkeMaxRows));
    std::vector<double> m, q;
    lcpNormalProblem(p.dense, m, q);
    return solveLemke(m, q);
}

} // namespace rubble
