// host/dynamics/contact_rows.cpp: CPU stage 5 for contacts: normal and friction rows per
// manifold point, warm-started from last step's impulses.
#include "host/dynamics/contact_rows.h"

#include <algorithm>
#include <cmath>

#include "host/core/assert.h"
#include "host/core/math.h"

namespace rubble {
namespace {

// Tangential speeds above this pick the sliding direction as the first tangent, m/s: the two
// friction rows are bounded separately, and a box bound is only exact along its axes.
constexpr float kSlidingSpeed = 1e-3f;

bool keyLess(const ContactImpulse& x, std::uint32_t a, std::uint32_t b, std::uint32_t feature) {
    if (x.a != a) return x.a < a;
    if (x.b != b) return x.b < b;
    return x.feature < feature;
}

// One row's Jacobian along d at offsets ra, rb: r x d and I^-1 (r x d) for each body, and
// 1 / (J M^-1 J^T) (0 when nothing can move).
struct RowJacobian {
    Lanes crossA, crossB, turnA, turnB;
    float mass;
};
RowJacobian rowJacobian(glm::vec3 d, glm::vec3 ra, glm::vec3 rb, float inverseMassA,
                        float inverseMassB, const glm::mat3& ia, const glm::mat3& ib) {
    // A body that does not move has no velocity to read and takes no impulse: zeros.
    const glm::vec3 crossA = inverseMassA > 0.0f ? glm::cross(ra, d) : glm::vec3(0.0f);
    const glm::vec3 crossB = inverseMassB > 0.0f ? glm::cross(rb, d) : glm::vec3(0.0f);
    const glm::vec3 turnA = inverseMassA > 0.0f ? ia * crossA : glm::vec3(0.0f);
    const glm::vec3 turnB = inverseMassB > 0.0f ? ib * crossB : glm::vec3(0.0f);
    const float k = inverseMassA + inverseMassB + glm::dot(crossA, turnA) + glm::dot(crossB, turnB);
    return RowJacobian{toLanes(crossA), toLanes(crossB), toLanes(turnA), toLanes(turnB),
                       k > 0.0f ? 1.0f / k : 0.0f};
}

// Hands last step's impulses to one manifold's new points (rows [first, first + count)): the
// same feature first, then the nearest unmatched old point within kWarmStartMatchDistance.
// `last` starts at the pair's run.
void warmStart(ContactRows& rows, std::size_t first, std::size_t count,
               std::span<const ContactImpulse> last) {
    const ContactKey& key = rows.keys[first];
    // A manifold has at most 4 points; more old points than 8 would be a different narrow phase.
    constexpr std::size_t kMaxOld = 8;
    std::size_t old = 0;
    while (old < last.size() && old < kMaxOld && last[old].a == key.a && last[old].b == key.b)
        ++old;
    if (old == 0) return;
    bool taken[kMaxOld] = {};
    bool matched[4] = {};
    auto take = [&](std::size_t k, const ContactImpulse& from) {
        rows.normals[first + k].impulse = from.normal;
        FrictionRows& f = rows.frictions[first + k];
        f.impulse[0] = glm::dot(from.friction, fromLanes(f.tangent[0]));
        f.impulse[1] = glm::dot(from.friction, fromLanes(f.tangent[1]));
    };
    for (std::size_t k = 0; k < count; ++k)
        for (std::size_t o = 0; o < old; ++o)
            if (!taken[o] && last[o].feature == rows.keys[first + k].feature) {
                take(k, last[o]);
                taken[o] = matched[k] = true;
                break;
            }
    for (std::size_t k = 0; k < count; ++k) {
        if (matched[k]) continue;
        float best = kWarmStartMatchDistance * kWarmStartMatchDistance;
        std::size_t pick = old;
        for (std::size_t o = 0; o < old; ++o) {
            if (taken[o]) continue;
            const glm::vec3 d = last[o].pointInA - rows.keys[first + k].pointInA;
            if (glm::dot(d, d) < best) {
                best = glm::dot(d, d);
                pick = o;
            }
        }
        if (pick == old) continue;
        take(k, last[pick]);
        taken[pick] = true;
    }
}

// Velocity of the point at offset r from a body's centre of mass, world.
glm::vec3 pointVelocity(const shared::BodyVelocity& v, glm::vec3 r) {
    return toVec3(v.linear) + glm::cross(toVec3(v.angular), r);
}

struct Bounce {
    float speed = 0.0f; ///< normal velocity to leave with, m/s (0: no bounce)
    float lift = 0.0f;  ///< the split pass's speed that lifts the bodies off the contact, m/s
};

// A bounce from the contact, for a point whose bodies approach at `before` m/s before this
// step's forces and `after` after them (positive: closing) across `gap` m. The forces'
// acceleration a = (after - before) / dt carries the approach over the gap, and only a meeting
// faster than kRestitutionThreshold bounces (at rest before the forces, nothing does, whatever
// dt). Symplectic Euler's positions are samples at the steps of the path whose velocity at the
// step's start is the stored one plus half a step of a, u0 = before + a dt / 2: on it the bodies
// meet at t_c = 2 gap / (u0 + u_c) with u_c = sqrt(u0^2 + 2 a gap), leave at e u_c, and at the
// step's end are e u_c tau - a tau^2 / 2 apart (tau = dt - t_c) with the stored velocity
// e u_c - a (dt / 2 - t_c). So the rebound keeps e^2 of the drop height to round-off.
Bounce bounceOf(float restitution, float before, float after, float gap, float dt) {
    if (restitution <= 0.0f) return {};
    const float closing = std::max(before, 0.0f);
    const float a = (after - before) / dt;
    const float meeting = closing * closing + 2.0f * a * gap;
    if (meeting <= kRestitutionThreshold * kRestitutionThreshold) return {};
    const float u0 = closing + 0.5f * a * dt;
    const float reach = u0 * u0 + 2.0f * a * gap;
    if (u0 <= 0.0f || reach <= 0.0f) return {};
    const float uc = std::sqrt(reach);
    const float tc = 2.0f * gap / (u0 + uc);
    const float tau = std::max(dt - tc, 0.0f);
    Bounce b;
    b.speed = restitution * uc - a * (0.5f * dt - tc);
    if (b.speed <= 0.0f) return {};
    b.lift = std::max(restitution * uc * tau - 0.5f * a * tau * tau, 0.0f) / dt;
    return b;
}

} // namespace

bool isJoinedPair(std::span<const BodyPair> joined, std::uint32_t a, std::uint32_t b) {
    if (joined.empty()) return false;
    const BodyPair key{std::min(a, b), std::max(a, b)};
    return std::binary_search(joined.begin(), joined.end(), key);
}

void tangentBasis(glm::vec3 n, glm::vec3& t1, glm::vec3& t2) {
    // Cross with the axis least aligned with n (Catto, "Computing a basis", 2014).
    if (std::abs(n.x) >= 0.57735f)
        t1 = glm::normalize(glm::vec3(n.y, -n.x, 0.0f));
    else
        t1 = glm::normalize(glm::vec3(0.0f, n.z, -n.y));
    t2 = glm::cross(n, t1);
}

void buildContactRows(std::span<const Manifold> manifolds, std::span<const shared::BodyPose> poses,
                      const SolverBodies& bodies,
                      std::span<const shared::BodyVelocity> beforeForces,
                      std::span<const MaterialDesc> materials,
                      std::span<const std::uint32_t> materialOf, std::span<const BodyPair> joined,
                      std::span<const ContactImpulse> last, const ContactRowSettings& settings,
                      ContactRows& rows) {
    rows.clear();
    const float dt = settings.dt;
    for (const Manifold& m : manifolds) {
        if (m.count == 0) continue;
        if (!bodies.moves(m.a) && !bodies.moves(m.b)) continue;
        if (isJoinedPair(joined, m.a, m.b)) continue;
        RUBBLE_ASSERT(m.count <= m.points.size());
        const MaterialDesc& matA = materials[materialOf[m.a]];
        const MaterialDesc& matB = materials[materialOf[m.b]];
        const float friction = std::sqrt(matA.friction * matB.friction);
        const float restitution = std::max(matA.restitution, matB.restitution);
        const glm::vec3 xa = toVec3(poses[m.a].position), xb = toVec3(poses[m.b].position);
        const SolverVelocity& bodyA = bodies.velocity[m.a];
        const SolverVelocity& bodyB = bodies.velocity[m.b];
        const float ima = bodies.inverseMass[m.a], imb = bodies.inverseMass[m.b];
        const glm::mat3& ia = bodies.inverseInertia[m.a];
        const glm::mat3& ib = bodies.inverseInertia[m.b];
        const glm::vec3 n = m.normal;
        glm::vec3 fixedTangent[2];
        tangentBasis(n, fixedTangent[0], fixedTangent[1]);
        const std::size_t first = rows.size();

        for (std::uint32_t k = 0; k < m.count; ++k) {
            const ContactPoint& p = m.points[k];
            const glm::vec3 ra = p.position - xa, rb = p.position - xb;
            const glm::vec3 relative =
                (fromLanes(bodyB.linear) + glm::cross(fromLanes(bodyB.angular), rb)) -
                (fromLanes(bodyA.linear) + glm::cross(fromLanes(bodyA.angular), ra));
            const float normalSpeed = glm::dot(relative, n);
            const glm::vec3 relativeBefore =
                pointVelocity(beforeForces[m.b], rb) - pointVelocity(beforeForces[m.a], ra);

            NormalRow nr;
            nr.a = m.a;
            nr.b = m.b;
            const RowJacobian jn = rowJacobian(n, ra, rb, ima, imb, ia, ib);
            nr.normal = toLanes(n);
            nr.crossA = jn.crossA;
            nr.crossB = jn.crossB;
            nr.turnA = jn.turnA;
            nr.turnB = jn.turnB;
            nr.inverseMassA = ima;
            nr.inverseMassB = imb;
            nr.mass = jn.mass;
            // Target: stop a touching approach, or let a gap close and no more; the penetration
            // beyond the slop is pushed out by the position pass.
            if (p.depth >= 0.0f) {
                const float push =
                    settings.baumgarte / dt * std::max(p.depth - settings.slop, 0.0f);
                nr.pushSpeed = std::min(push, kMaxPushSpeed);
                nr.targetSpeed = 0.0f;
            } else {
                nr.targetSpeed = p.depth / dt;
            }
            // A bounce leaves the contact at e times the speed the bodies meet it with.
            const Bounce bounce = bounceOf(restitution, -glm::dot(relativeBefore, n), -normalSpeed,
                                           std::max(-p.depth, 0.0f), dt);
            nr.bounceSpeed = bounce.speed;
            nr.bounceLift = bounce.lift;
            rows.normals.push_back(nr);

            // Tangents: along the sliding velocity when there is one, else a fixed basis.
            FrictionRows fr;
            fr.a = m.a;
            fr.b = m.b;
            fr.inverseMassA = ima;
            fr.inverseMassB = imb;
            fr.friction = friction;
            const glm::vec3 sliding = relative - n * normalSpeed;
            const float slidingSpeed = glm::length(sliding);
            glm::vec3 tangent[2];
            if (slidingSpeed > kSlidingSpeed) {
                tangent[0] = sliding / slidingSpeed;
                tangent[1] = glm::cross(n, tangent[0]);
            } else {
                tangent[0] = fixedTangent[0];
                tangent[1] = fixedTangent[1];
            }
            for (int d = 0; d < 2; ++d) {
                const RowJacobian jt = rowJacobian(tangent[d], ra, rb, ima, imb, ia, ib);
                fr.tangent[d] = toLanes(tangent[d]);
                fr.crossA[d] = jt.crossA;
                fr.crossB[d] = jt.crossB;
                fr.turnA[d] = jt.turnA;
                fr.turnB[d] = jt.turnB;
                fr.mass[d] = jt.mass;
            }
            rows.frictions.push_back(fr);

            ContactKey key;
            key.a = m.a;
            key.b = m.b;
            key.feature = p.feature;
            key.pointInA = toVec3(shared::quatRotateInverse(poses[m.a].orientation, toFloat4(ra)));
            rows.keys.push_back(key);
        }
        for (std::uint32_t k = 0; k < m.count; ++k) rows.slot.push_back(k);
        if (settings.warmStart) {
            // Last step's impulses of this pair: a sorted run.
            const auto run = std::lower_bound(
                last.begin(), last.end(), 0u,
                [&](const ContactImpulse& x, std::uint32_t) { return keyLess(x, m.a, m.b, 0u); });
            warmStart(rows, first, m.count, last.subspan(std::size_t(run - last.begin())));
        }
    }
    interleaveContactRows(rows);
}

void interleaveContactRows(ContactRows& rows) {
    // Stable counting sort by slot: manifold order is kept within each slot.
    std::size_t start[5] = {0, 0, 0, 0, 0};
    for (const std::uint8_t k : rows.slot) ++start[k + 1];
    for (int k = 0; k < 4; ++k) start[k + 1] += start[k];
    rows.scratchNormals.resize(rows.size());
    rows.scratchFrictions.resize(rows.size());
    rows.scratchKeys.resize(rows.size());
    rows.built.resize(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::size_t to = start[rows.slot[i]]++;
        rows.built[to] = std::uint32_t(i);
        rows.scratchNormals[to] = rows.normals[i];
        rows.scratchFrictions[to] = rows.frictions[i];
        rows.scratchKeys[to] = rows.keys[i];
    }
    std::swap(rows.normals, rows.scratchNormals);
    std::swap(rows.frictions, rows.scratchFrictions);
    std::swap(rows.keys, rows.scratchKeys);
    rows.slot.clear();
}

void storeContactImpulses(const ContactRows& rows, std::span<const ContactImpulse> previous,
                          const SolverBodies& bodies, std::vector<ContactImpulse>& impulses,
                          std::vector<ContactImpulse>& scratch) {
    scratch.resize(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const ContactKey& key = rows.keys[i];
        const FrictionRows& f = rows.frictions[i];
        ContactImpulse& c = scratch[rows.built.empty() ? i : rows.built[i]];
        c.a = key.a;
        c.b = key.b;
        c.feature = key.feature;
        c.pointInA = key.pointInA;
        c.normal = rows.normals[i].impulse;
        c.friction = fromLanes(f.tangent[0] * f.impulse[0] + f.tangent[1] * f.impulse[1]);
    }
    // The narrow phase hands the manifolds over in pair order; anything else is sorted here.
    const auto byPair = [](const ContactImpulse& x, const ContactImpulse& y) {
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    };
    if (!std::is_sorted(scratch.begin(), scratch.end(), byPair))
        std::stable_sort(scratch.begin(), scratch.end(), byPair);
    // Merge in the still pairs' impulses; a pair with rows has a moving body, so none repeats.
    impulses.clear();
    std::size_t next = 0;
    for (const ContactImpulse& old : previous) {
        if (bodies.moves(old.a) || bodies.moves(old.b)) continue;
        while (next < scratch.size() && byPair(scratch[next], old))
            impulses.push_back(scratch[next++]);
        impulses.push_back(old);
    }
    impulses.insert(impulses.end(), scratch.begin() + std::ptrdiff_t(next), scratch.end());
}

} // namespace rubble
