// host/collision/collision_world.cpp: CPU stages 3 and 4 over a world's arrays: body boxes and
// planes into the broad phase, pairs through the narrow phase into manifolds.
#include "host/collision/collision_world.h"

#include <algorithm>

#include "host/collision/narrow_phase.h"
#include "host/core/limits.h"
#include "host/core/math.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

void updateTransforms(WorldState& s) {
    s.collision.transforms.resize(s.bodyCount());
    for (std::uint32_t i = 0; i < s.bodyCount(); ++i)
        s.collision.transforms[i] = transformOf(s.poses[i]);
}

// The world box of a shape: a hull's local box turned (|R| times its half extents), a sphere's
// centre plus its radius; grown by the margin.
Aabb worldBox(const Shape& shape, const Transform& t, float margin) {
    if (shape.type == ShapeType::Sphere) {
        const glm::vec3 r(shape.radius + margin);
        return Aabb{t.translation - r, t.translation + r};
    }
    const HalfEdgeMesh& m = shape.halfEdge;
    const glm::vec3 centre = t.apply((m.boundsMin + m.boundsMax) * 0.5f);
    const glm::vec3 half = (m.boundsMax - m.boundsMin) * 0.5f;
    glm::vec3 extent(margin);
    for (int c = 0; c < 3; ++c) // glm is column-major: rotation[c][r]
        extent += glm::abs(t.rotation[c]) * half[c];
    return Aabb{centre - extent, centre + extent};
}

// How much closer two bodies can come this step: their relative translation plus what their
// turning can add. Bodies falling side by side close nothing, so they get no speculative gap.
float pairReach(const WorldState& s, const BodyPair& pair, const std::vector<float>& spin) {
    const glm::vec3 relative =
        toVec3(s.velocities[pair.b].linear) - toVec3(s.velocities[pair.a].linear);
    return glm::length(relative) * s.options.dt + spin[pair.a] + spin[pair.b];
}

} // namespace

void runBroadPhase(WorldState& s) {
    CollisionCache& c = s.collision;
    updateTransforms(s);
    const std::uint32_t n = s.bodyCount();
    c.boxes.resize(n);
    c.flags.resize(n);
    c.reach.resize(n);
    c.spin.resize(n);
    c.planes.clear();
    const float dt = s.options.dt;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Shape& shape = s.shapes[s.shapeOf[i]];
        // The farthest any point of the body moves this step with its current velocities.
        c.spin[i] = glm::length(toVec3(s.velocities[i].angular)) * shape.boundingRadius * dt;
        c.reach[i] = glm::length(toVec3(s.velocities[i].linear)) * dt + c.spin[i];
        const bool inactive =
            s.isStatic(i) || (s.masses[i].flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP));
        c.flags[i] = inactive ? kBroadPhaseInactive : 0;
        if (shape.type == ShapeType::Plane) {
            c.flags[i] |= kBroadPhaseNoBox;
            const glm::vec3 normal = c.transforms[i].rotate(shape.normal);
            const float offset = shape.offset + glm::dot(normal, c.transforms[i].translation);
            // Grown by the margin like the boxes.
            c.planes.push_back(PlaneProxy{i, normal, offset + kContactMargin});
            c.boxes[i] = Aabb{};
            continue;
        }
        c.boxes[i] = worldBox(shape, c.transforms[i], kContactMargin + c.reach[i]);
    }
    c.broadPhase.pairLimit = pairBudget(n);
    findPairs(c.boxes, c.flags, c.planes, s.pairs, c.broadPhase);
    if (c.broadPhase.overflowed)
        s.stepFailure = limitError("broadPhase", "broad-phase pairs", c.broadPhase.pairLimit + 1,
                                   c.broadPhase.pairLimit, s.step + 1,
                                   "bodies overlap each other in large numbers");
    // Bodies joined to each other do not collide: their pairs leave before the narrow phase, so
    // that no contact between them is computed, counted or drawn (the pairs keep their order).
    if (!s.joined.empty())
        std::erase_if(s.pairs, [&](const BodyPair& p) {
            return std::binary_search(s.joined.begin(), s.joined.end(),
                                      BodyPair{std::min(p.a, p.b), std::max(p.a, p.b)});
        });
    s.stats.pairCount = std::uint32_t(s.pairs.size());
}

void runNarrowPhase(WorldState& s) {
    CollisionCache& c = s.collision;
    updateTransforms(s);
    s.manifolds.clear();
    c.nextFeatures.clear();
    std::uint32_t contacts = 0;
    float deepest = 0.0f;
    // Both lists are sorted by pair: walk last step's features alongside.
    std::size_t cached = 0;
    for (const BodyPair& pair : s.pairs) {
        while (cached < c.features.size() && c.features[cached].pair < pair) ++cached;
        HullPairCache cache = cached < c.features.size() && c.features[cached].pair == pair
                                  ? c.features[cached].cache
                                  : HullPairCache{};
        const float margin = kContactMargin + pairReach(s, pair, c.spin);
        const PairContact pc =
            collideShapes(s.shapes[s.shapeOf[pair.a]], c.transforms[pair.a],
                          s.shapes[s.shapeOf[pair.b]], c.transforms[pair.b], cache, margin);
        if (cache.reusable) c.nextFeatures.push_back({pair, cache});
        if (pc.contacts.count == 0) continue;
        Manifold m;
        m.a = pair.a;
        m.b = pair.b;
        m.normal = pc.contacts.normal;
        m.count = pc.contacts.count;
        for (std::uint32_t i = 0; i < m.count; ++i) {
            const LocalContact& p = pc.contacts.points[i];
            m.points[i] = ContactPoint{p.position, p.depth, p.feature, m.normal};
            deepest = std::max(deepest, p.depth);
        }
        contacts += m.count;
        s.manifolds.push_back(m);
        if (contacts > contactBudget(s.bodyCount())) {
            s.stepFailure = limitError("narrowPhase", "contact points", contacts,
                                       contactBudget(s.bodyCount()), s.step + 1,
                                       "bodies overlap each other in large numbers");
            break;
        }
    }
    std::swap(c.features, c.nextFeatures);
    s.stats.contactCount = contacts;
    s.stats.largestPenetration = deepest;
}

} // namespace rubble
