// host/dynamics/jacobi.cpp: OpenCL stage 5 on the CPU; twin of kernels/jacobi.cl.
#include "host/dynamics/jacobi.h"

#include <algorithm>
#include <cmath>

#include "host/core/assert.h"
#include "host/core/math.h"
#include "host/world/world_state.h"

namespace rubble {

using namespace shared;

std::vector<float4> bodySurfaces(const WorldState& s) {
    std::vector<float4> out(s.bodyCount());
    for (std::uint32_t b = 0; b < s.bodyCount(); ++b) {
        const MaterialDesc& m = s.materials[s.materialOf[b]];
        out[b] = vec4(m.friction, m.restitution, 0.0f);
    }
    return out;
}

float jacobiRelaxation(const SolverOptions& o) {
    return o.relaxation * kJacobiOverRelaxation;
}

SolverParams solverParams(const SimulationOptions& o) {
    const SolverOptions& s = o.solver;
    const bool particles = o.collisionMethod() == CollisionMethod::Particles;
    const float slop = particles ? particleSlopItem(s.slop, o.collision.particleSpacing) : s.slop;
    return SolverParams{s.baumgarte, slop, 1.0f / o.dt, s.relaxation};
}

void manifoldsToContacts(std::span<const Manifold> manifolds, std::vector<ParticleContact>& out) {
    out.clear();
    for (const Manifold& m : manifolds)
        for (std::uint32_t k = 0; k < m.count; ++k) {
            const ContactPoint& p = m.points[k];
            ParticleContact c{};
            c.point = toFloat4(p.position, p.depth);
            c.normal = toFloat4(p.normal);
            c.a = m.a;
            c.b = m.b;
            c.particleA = m.a;
            c.featureB = p.feature;
            out.push_back(c);
        }
}

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

namespace {

std::span<const ParticleContact> contactsOf(WorldState& s) {
    if (s.options.collisionMethod() == CollisionMethod::Particles) return s.particles.contacts;
    manifoldsToContacts(s.manifolds, s.jacobi.fromManifolds);
    return s.jacobi.fromManifolds;
}

} // namespace

void runBuildJacobiRows(WorldState& s) {
    JacobiState& j = s.jacobi;
    const std::span<const ParticleContact> contacts = contactsOf(s);
    buildBodyLists(contacts, s.masses, j);
    if (s.options.solver.warmStart)
        matchWarmStart(contacts, j.previous, j.warm);
    else
        j.warm.assign(contacts.size(), vec4(0.0f, 0.0f, 0.0f));
    buildJacobiRows(contacts, s.poses, s.velocitiesAtStart, s.masses, bodySurfaces(s),
                    solverParams(s.options), j.warm, j);
}

void runSolveJacobi(WorldState& s) {
    JacobiState& j = s.jacobi;
    solveJacobi(j, s.velocitiesBeforeSolve, s.masses, s.poses, s.velocities,
                s.options.solver.iterations, jacobiRelaxation(s.options.solver));
    if (s.options.solver.warmStart) rememberImpulses(contactsOf(s), j.rows, j.previous);
    s.stats.solverResidual = j.residuals.empty() ? 0.0f : j.residuals.back();
}

} // namespace rubble
