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

// 1 / (J M^-1 J^T) for a row with direction d at offsets ra, rb; 0 when nothing can move.
float rowMass(const ContactRow& r, int k) {
    const float k0 = r.inverseMassA + r.inverseMassB + glm::dot(r.crossA[k], r.turnA[k]) +
                     glm::dot(r.crossB[k], r.turnB[k]);
    return k0 > 0.0f ? 1.0f / k0 : 0.0f;
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
                      const SolverBodies& bodies, std::span<const MaterialDesc> materials,
                      std::span<const std::uint32_t> materialOf,
                      std::span<const BodyPair> joined, std::span<const ContactImpulse> last,
                      const ContactRowSettings& settings, std::vector<ContactRow>& rows) {
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
        const glm::vec3 va = bodies.linear[m.a], wa = bodies.angular[m.a];
        const glm::vec3 vb = bodies.linear[m.b], wb = bodies.angular[m.b];
        const glm::mat3& ia = bodies.inverseInertia[m.a];
        const glm::mat3& ib = bodies.inverseInertia[m.b];
        // Last step's impulses of this pair: a sorted run.
        const auto first = std::lower_bound(
            last.begin(), last.end(), 0u,
            [&](const ContactImpulse& x, std::uint32_t) { return keyLess(x, m.a, m.b, 0u); });

        for (std::uint32_t k = 0; k < m.count; ++k) {
            const ContactPoint& p = m.points[k];
            ContactRow r;
            r.a = m.a;
            r.b = m.b;
            r.feature = p.feature;
            r.inverseMassA = bodies.inverseMass[m.a];
            r.inverseMassB = bodies.inverseMass[m.b];
            r.friction = friction;
            const glm::vec3 n = m.normal;
            const glm::vec3 ra = p.position - xa, rb = p.position - xb;
            const glm::vec3 relative = (vb + glm::cross(wb, rb)) - (va + glm::cross(wa, ra));
            const float normalSpeed = glm::dot(relative, n);

            // Tangents: along the sliding velocity when there is one, else a fixed basis.
            const glm::vec3 sliding = relative - n * normalSpeed;
            const float slidingSpeed = glm::length(sliding);
            glm::vec3 t1, t2;
            if (slidingSpeed > kSlidingSpeed) {
                t1 = sliding / slidingSpeed;
                t2 = glm::cross(n, t1);
            } else {
                tangentBasis(n, t1, t2);
            }
            r.direction[0] = n;
            r.direction[1] = t1;
            r.direction[2] = t2;
            for (int d = 0; d < 3; ++d) {
                r.crossA[d] = glm::cross(ra, r.direction[d]);
                r.crossB[d] = glm::cross(rb, r.direction[d]);
                r.turnA[d] = ia * r.crossA[d];
                r.turnB[d] = ib * r.crossB[d];
                r.mass[d] = rowMass(r, d);
            }

            // Normal target speed: push out the penetration beyond the slop, bounce a fast
            // approach, or let a gap close and no more.
            const float approach = -normalSpeed;
            const bool bounces = restitution > 0.0f && approach > kRestitutionThreshold;
            if (p.depth >= 0.0f) {
                r.targetSpeed = settings.baumgarte / dt * std::max(p.depth - settings.slop, 0.0f);
                if (bounces) r.targetSpeed = std::max(r.targetSpeed, restitution * approach);
            } else {
                const bool closes = approach * dt > -p.depth;
                r.targetSpeed = bounces && closes ? restitution * approach : p.depth / dt;
            }

            // Warm start from the same feature's impulses, friction projected on the new tangents.
            r.impulse[0] = r.impulse[1] = r.impulse[2] = 0.0f;
            if (settings.warmStart) {
                for (auto it = first; it != last.end() && it->a == m.a && it->b == m.b; ++it) {
                    if (it->feature != p.feature) continue;
                    r.impulse[0] = it->normal;
                    r.impulse[1] = glm::dot(it->friction, t1);
                    r.impulse[2] = glm::dot(it->friction, t2);
                    break;
                }
            }
            rows.push_back(r);
        }
    }
}

void storeContactImpulses(std::span<const ContactRow> rows, std::vector<ContactImpulse>& impulses) {
    impulses.clear();
    impulses.reserve(rows.size());
    for (const ContactRow& r : rows) {
        ContactImpulse c;
        c.a = r.a;
        c.b = r.b;
        c.feature = r.feature;
        c.normal = r.impulse[0];
        c.friction = r.direction[1] * r.impulse[1] + r.direction[2] * r.impulse[2];
        impulses.push_back(c);
    }
    std::sort(impulses.begin(), impulses.end(), [](const ContactImpulse& x, const ContactImpulse& y) {
        return keyLess(x, y.a, y.b, y.feature);
    });
}

} // namespace rubble
