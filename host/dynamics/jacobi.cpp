// host/dynamics/jacobi.cpp: OpenCL stage 5 on the CPU; twin of kernels/jacobi.cl.
#include "host/dynamics/jacobi.h"

#include <algorithm>
#include <cmath>

#include "host/core/assert.h"
#include "host/core/math.h"

namespace rubble {

using namespace shared;

namespace {

// A body whose rows are listed (its velocity gathers them): dynamic and awake. Sleeping bodies
// take part as walls (the device lists kinematic bodies too, for their impulses).
bool listed(const BodyMass& m) {
    return m.inverseMass != 0.0f && listedBodyItem(m.flags);
}

// A sleeping body's mass in a row: a wall's.
BodyMass rowMass(const BodyMass& m) {
    return (m.flags & RUBBLE_BODY_ASLEEP) ? wallMassItem(m) : m;
}

} // namespace

void buildBodyLists(std::span<const ParticleContact> contacts, std::span<const BodyMass> masses,
                    JacobiState& j) {
    const std::size_t n = masses.size();
    j.bodyCount.assign(n, 0);
    for (const ParticleContact& c : contacts) {
        if (listed(masses[c.a])) ++j.bodyCount[c.a];
        if (listed(masses[c.b])) ++j.bodyCount[c.b];
    }
    j.bodyStart.assign(n + 1, 0);
    for (std::size_t b = 0; b < n; ++b) j.bodyStart[b + 1] = j.bodyStart[b] + j.bodyCount[b];
    j.bodyList.resize(j.bodyStart[n]);
    std::vector<std::uint32_t> cursor(j.bodyStart.begin(), j.bodyStart.end() - 1);
    for (std::uint32_t r = 0; r < contacts.size(); ++r) {
        if (listed(masses[contacts[r].a])) j.bodyList[cursor[contacts[r].a]++] = 2 * r;
        if (listed(masses[contacts[r].b])) j.bodyList[cursor[contacts[r].b]++] = 2 * r + 1;
    }
}

void buildJacobiRows(std::span<const ParticleContact> contacts, std::span<const BodyPose> poses,
                     std::span<const BodyVelocity> approach, std::span<const BodyMass> masses,
                     std::span<const float4> surfaces, SolverParams params,
                     std::span<const float4> warm, JacobiState& j) {
    RUBBLE_ASSERT(warm.size() == contacts.size());
    j.rows.resize(contacts.size());
    for (std::size_t r = 0; r < contacts.size(); ++r)
        j.rows[r] = contactRowFromContactItem(
            contacts[r], poses[contacts[r].a], poses[contacts[r].b], approach[contacts[r].a],
            approach[contacts[r].b], rowMass(masses[contacts[r].a]), rowMass(masses[contacts[r].b]),
            surfaces[contacts[r].a], surfaces[contacts[r].b], j.bodyCount[contacts[r].a],
            j.bodyCount[contacts[r].b], params, warm[r]);
}

void matchWarmStart(std::span<const ParticleContact> contacts,
                    std::span<const WarmImpulse> previous, std::vector<float4>& warm) {
    warm.assign(contacts.size(), vec4(0.0f, 0.0f, 0.0f));
    for (std::size_t r = 0; r < contacts.size(); ++r) {
        WarmImpulse key;
        key.particleA = contacts[r].particleA;
        key.featureB = contacts[r].featureB;
        key.b = contacts[r].b;
        const auto it = std::lower_bound(previous.begin(), previous.end(), key);
        if (it != previous.end() && !(key < *it)) warm[r] = it->lambda;
    }
}

void rememberImpulses(std::span<const ParticleContact> contacts,
                      std::span<const shared::ContactRow> rows,
                      std::vector<WarmImpulse>& previous) {
    previous.resize(contacts.size());
    for (std::size_t r = 0; r < contacts.size(); ++r)
        previous[r] =
            WarmImpulse{contacts[r].particleA, contacts[r].featureB, contacts[r].b, rows[r].lambda};
    std::sort(previous.begin(), previous.end());
}

float solveJacobiRows(std::span<shared::ContactRow> rows, std::span<const BodyVelocity> velocities,
                      float relaxation) {
    float residual = 0.0f;
    for (shared::ContactRow& r : rows) {
        const float4 next = solveContactItem(r, velocities[r.a], velocities[r.b], relaxation);
        residual = std::max(residual, impulseChangeItem(r.lambda, next));
        r.lambda = next;
    }
    return residual;
}

void gatherJacobi(std::span<const shared::ContactRow> rows, const JacobiState& j,
                  std::span<const BodyVelocity> before, std::span<const BodyMass> masses,
                  std::span<const BodyPose> poses, std::span<BodyVelocity> velocities) {
    for (std::size_t b = 0; b < masses.size(); ++b) {
        if (!listed(masses[b])) continue;
        float4 linear = vec4(0.0f, 0.0f, 0.0f), angular = vec4(0.0f, 0.0f, 0.0f);
        for (std::uint32_t e = j.bodyStart[b]; e < j.bodyStart[b + 1]; ++e) {
            const std::uint32_t entry = j.bodyList[e];
            const shared::ContactRow& r = rows[entry >> 1];
            const BodyImpulse i = rowImpulseOnBodyItem(r, entry & 1u);
            linear = add4(linear, i.linear);
            angular = add4(angular, i.angular);
        }
        velocities[b] =
            applyImpulseSumItem(before[b], linear, angular, masses[b].inverseMass,
                                inverseInertiaWorldItem(masses[b], poses[b].orientation));
    }
}

void solveJacobi(JacobiState& j, std::span<const BodyVelocity> before,
                 std::span<const BodyMass> masses, std::span<const BodyPose> poses,
                 std::span<BodyVelocity> velocities, int iterations, float relaxation) {
    j.residuals.clear();
    // Warm-started impulses act before the first sweep.
    gatherJacobi(j.rows, j, before, masses, poses, velocities);
    for (int k = 0; k < iterations; ++k) {
        j.residuals.push_back(solveJacobiRows(j.rows, velocities, relaxation));
        gatherJacobi(j.rows, j, before, masses, poses, velocities);
    }
}

} // namespace rubble
