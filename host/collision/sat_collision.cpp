// host/collision/sat_collision.cpp: CPU stages broadPhase and narrowPhase of the SAT method over
// the body arrays: body boxes and planes into the broad phase, pairs through the narrow phase
// (rubble/shared/narrow_phase.h, as the device runs it) into manifolds.
#include "host/collision/sat_collision.h"

#include <algorithm>

#include "host/core/limits.h"
#include "host/core/math.h"
#include "rubble/shared/narrow_phase.h"

namespace rubble {
namespace {

// The scene's shapes flattened, and clipping buffers for their largest face.
void flattenScene(const CollisionScene& scene, CollisionCache& c) {
    c.hulls = flattenHulls(scene.shapes);
    c.hullsOf = scene.shapes.data();
    const std::size_t capacity = 2 * std::size_t(c.hulls.largestFace) + 1;
    c.polygon.resize(capacity);
    c.scratch.resize(capacity);
    c.candidates.resize(capacity);
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
float pairReach(BodiesView bodies, const BodyPair& pair, const std::vector<float>& spin, float dt) {
    const glm::vec3 relative =
        toVec3(bodies.velocities[pair.b].linear) - toVec3(bodies.velocities[pair.a].linear);
    return glm::length(relative) * dt + spin[pair.a] + spin[pair.b];
}

} // namespace

Status SatCollision::broadPhase(const CollisionScene& scene, BodiesView bodies,
                                const StepParams& params, StepContacts& out) {
    CollisionCache& c = cache_;
    const std::uint32_t n = bodies.count();
    c.boxes.resize(n);
    c.flags.resize(n);
    c.reach.resize(n);
    c.spin.resize(n);
    c.planes.clear();
    const float dt = params.dt;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Shape& shape = scene.shapes[bodies.shapeOf[i]];
        const Transform t = transformOf(bodies.poses[i]);
        // The farthest any point of the body moves this step with its current velocities.
        c.spin[i] = glm::length(toVec3(bodies.velocities[i].angular)) * shape.boundingRadius * dt;
        c.reach[i] = glm::length(toVec3(bodies.velocities[i].linear)) * dt + c.spin[i];
        const bool inactive = bodies.isStatic(i) ||
                              (bodies.masses[i].flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP));
        c.flags[i] = inactive ? kBroadPhaseInactive : 0;
        if (shape.type == ShapeType::Plane) {
            c.flags[i] |= kBroadPhaseNoBox;
            const glm::vec3 normal = t.rotate(shape.normal);
            const float offset = shape.offset + glm::dot(normal, t.translation);
            // Grown by the margin like the boxes.
            c.planes.push_back(PlaneProxy{i, normal, offset + RUBBLE_CONTACT_MARGIN});
            c.boxes[i] = Aabb{};
            continue;
        }
        c.boxes[i] = worldBox(shape, t, RUBBLE_CONTACT_MARGIN + c.reach[i]);
    }
    c.broadPhase.pairLimit = pairBudget(n);
    findPairs(c.boxes, c.flags, c.planes, out.pairs, c.broadPhase);
    if (c.broadPhase.overflowed)
        return limitError("broadPhase", "broad-phase pairs", c.broadPhase.pairLimit + 1,
                          c.broadPhase.pairLimit, params.step + 1,
                          "bodies overlap each other in large numbers");
    // Bodies joined to each other do not collide: their pairs leave before the narrow phase, so
    // that no contact between them is computed, counted or drawn (the pairs keep their order).
    if (!scene.joined.empty())
        std::erase_if(out.pairs, [&](const BodyPair& p) {
            return std::binary_search(scene.joined.begin(), scene.joined.end(),
                                      BodyPair{std::min(p.a, p.b), std::max(p.a, p.b)});
        });
    return {};
}

Status SatCollision::narrowPhase(const CollisionScene& scene, BodiesView bodies,
                                 const StepParams& params, StepContacts& out) {
    CollisionCache& c = cache_;
    // A stage used without rebuild (tests, benchmarks) flattens the shapes on first use.
    if (c.hullsOf != scene.shapes.data() || c.hulls.shapes.size() != scene.shapes.size())
        flattenScene(scene, c);
    const shared::HullArrays arrays = hullArraysOf(c.hulls);
    const shared::ClipBuffers buffers{c.polygon.data(), c.scratch.data(), c.candidates.data()};
    c.transforms.resize(bodies.count());
    for (std::uint32_t i = 0; i < bodies.count(); ++i)
        c.transforms[i] = shared::transformOfPose(bodies.poses[i]);
    out.manifolds.clear();
    c.nextFeatures.clear();
    std::size_t contacts = 0;
    const std::size_t budget = contactBudget(bodies.count());
    float deepest = 0.0f;
    // Both lists are sorted by pair: walk last step's features alongside.
    std::size_t cached = 0;
    for (const BodyPair& pair : out.pairs) {
        while (cached < c.features.size() && c.features[cached].pair < pair) ++cached;
        shared::PairCache cache = cached < c.features.size() && c.features[cached].pair == pair
                                      ? c.features[cached].cache
                                      : shared::emptyPairCacheItem();
        const float margin = RUBBLE_CONTACT_MARGIN + pairReach(bodies, pair, c.spin, params.dt);
        const shared::ContactManifold found = shared::collideShapesClippingInItem(
            arrays, c.hulls.shapes[bodies.shapeOf[pair.a]], c.transforms[pair.a],
            c.hulls.shapes[bodies.shapeOf[pair.b]], c.transforms[pair.b], &cache, margin, buffers);
        if (cache.reusable) c.nextFeatures.push_back({pair, cache});
        if (found.count == 0) continue;
        Manifold m;
        m.a = pair.a;
        m.b = pair.b;
        m.normal = toVec3(found.normal);
        m.count = found.count;
        for (std::uint32_t i = 0; i < m.count; ++i) {
            const shared::float4 p = found.points[i];
            m.points[i] = ContactPoint{toVec3(p), p.w, found.features[i], m.normal};
            deepest = std::max(deepest, p.w);
        }
        contacts += m.count;
        out.manifolds.push_back(m);
        if (contacts > budget) {
            // Bodies piled into each other: stop before the manifolds and rows fill memory.
            out.manifolds.clear();
            out.points.clear();
            out.contactCount = 0;
            return limitError("narrowPhase", "contact points", contacts, budget, params.step + 1,
                              "bodies overlap each other in large numbers");
        }
    }
    std::swap(c.features, c.nextFeatures);
    out.contactCount = std::uint32_t(contacts);
    out.largestPenetration = deepest;
    if (form_ == ContactForm::Points) manifoldsToContacts(out.manifolds, out.points);
    return {};
}

void SatCollision::contactPoints(const StepContacts& contacts,
                                 std::vector<shared::ParticleContact>& points) const {
    manifoldsToContacts(contacts.manifolds, points);
}

Status SatCollision::rebuild(const CollisionScene& scene, BodiesView, float) {
    flattenScene(scene, cache_);
    cache_.features.clear();
    cache_.nextFeatures.clear();
    return {};
}

void manifoldsToContacts(std::span<const Manifold> manifolds,
                         std::vector<shared::ParticleContact>& out) {
    out.clear();
    for (const Manifold& m : manifolds)
        for (std::uint32_t k = 0; k < m.count; ++k) {
            const ContactPoint& p = m.points[k];
            shared::ParticleContact c{};
            c.point = toFloat4(p.position, p.depth);
            c.normal = toFloat4(p.normal);
            c.a = m.a;
            c.b = m.b;
            c.particleA = m.a;
            c.featureB = p.feature;
            out.push_back(c);
        }
}

} // namespace rubble
