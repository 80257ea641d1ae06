// host/collision/sat_collision.cpp: CPU stages broadPhase and narrowPhase of the SAT method over
// the body arrays: body boxes and planes into the broad phase, pairs through the narrow phase
// (rubble/shared/narrow_phase.h, as the device runs it) into manifolds.
#include "host/collision/sat_collision.h"

#include <algorithm>

#include "host/collision/capsule_contact.h"
#include "host/core/assert.h"
#include "host/core/limits.h"
#include "host/core/math.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/contact_recycling.h"

namespace rubble {
namespace {

bool movesAtAll(const shared::BodyVelocity& v) {
    return shared::dot3(v.linear, v.linear) > 0.0f || shared::dot3(v.angular, v.angular) > 0.0f;
}

// The scene's shapes flattened, and clipping buffers for their largest face.
void flattenScene(const CollisionScene& scene, CollisionCache& c) {
    c.hulls = flattenHulls(scene.shapes);
    c.hullsOf = scene.shapes.data();
    c.clip = ClipSpace(c.hulls.largestFace);
}

} // namespace

Status SatCollision::broadPhase(const CollisionScene& scene, BodiesView bodies,
                                const StepParams& params, StepContacts& out) {
    CollisionCache& c = cache_;
    // A stage used without rebuild (tests, benchmarks) flattens the shapes on first use.
    if (c.hullsOf != scene.shapes.data() || c.hulls.shapes.size() != scene.shapes.size())
        flattenScene(scene, c);
    const std::uint32_t n = bodies.count();
    c.transforms.resize(n);
    c.boxes.resize(n);
    c.flags.resize(n);
    c.spin.resize(n);
    c.planes.clear();
    const float dt = params.dt;
    bool anyMovingKinematic = false;
    // The per-body math is the device's (rubble/shared/broad_phase.h, kernels/broad_phase.cl).
    for (std::uint32_t i = 0; i < n; ++i) {
        const shared::HullShape& shape = c.hulls.shapes[bodies.shapeOf[i]];
        const shared::RigidTransform& t = c.transforms[i] =
            shared::transformOfPose(bodies.poses[i]);
        // The farthest any point of the body moves this step with its current velocities.
        c.spin[i] = shared::spinItem(bodies.velocities[i], shape.boundingRadius, dt);
        const std::uint32_t flags = bodies.masses[i].flags;
        // A kinematic body that moves pairs with sleeping bodies too, so that it wakes them.
        const bool movingKinematic =
            (flags & RUBBLE_BODY_KINEMATIC) && movesAtAll(bodies.velocities[i]);
        const bool inactive = !movingKinematic && (bodies.isStatic(i) ||
                                                   (flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP)));
        anyMovingKinematic = anyMovingKinematic || movingKinematic;
        c.flags[i] = inactive ? kBroadPhaseInactive : 0;
        if (shape.kind == RUBBLE_SHAPE_PLANE) {
            c.flags[i] |= kBroadPhaseNoBox;
            const shared::float4 plane = shared::worldPlaneItem(shape, t);
            // Grown by the margin like the boxes.
            c.planes.push_back(PlaneProxy{i, toVec3(plane), plane.w + RUBBLE_CONTACT_MARGIN});
            c.boxes[i] = Aabb{};
            continue;
        }
        // Continuous collision: grown by how far the body can move this step, or swept along
        // the motion of a body much faster than its size (shared::stepBoxItem, as the device).
        const shared::BodyBox box =
            params.continuous
                ? shared::stepBoxItem(shape, t, bodies.velocities[i], c.spin[i], dt)
                : shared::worldBoxItem(shape, t, RUBBLE_CONTACT_MARGIN);
        c.boxes[i] = Aabb{toVec3(box.min), toVec3(box.max)};
    }
    c.broadPhase.pairLimit = pairBudget(n);
    findPairs(c.boxes, c.flags, c.planes, out.pairs, c.broadPhase);
    if (c.broadPhase.overflowed)
        return limitError("broadPhase", "broad-phase pairs", c.broadPhase.pairLimit + 1,
                          c.broadPhase.pairLimit, params.step + 1,
                          "bodies overlap each other in large numbers");
    // A moving kinematic body met static and other kinematic bodies too: nothing moves them.
    if (anyMovingKinematic)
        std::erase_if(out.pairs, [&](const BodyPair& p) {
            return bodies.masses[p.a].inverseMass == 0.0f && bodies.masses[p.b].inverseMass == 0.0f;
        });
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
    // The shapes, transforms and spins are the broad phase's of this step.
    RUBBLE_ASSERT(c.transforms.size() == bodies.count());
    const shared::HullArrays arrays = hullArraysOf(c.hulls);
    const shared::ClipBuffers buffers = c.clip.buffers();
    out.manifolds.clear();
    c.nextFeatures.clear();
    c.nextRecycled.clear();
    c.levelCandidates.beginStep();
    c.levelRecycled.beginStep();
    // Kept manifolds only from a step that kept them for every feature.
    const bool recycle = params.recycleContacts;
    const bool haveRecycled = recycle && c.recycled.size() == c.features.size();
    std::size_t contacts = 0;
    const std::size_t budget = contactBudget(bodies.count());
    float deepest = 0.0f;
    // Both lists are sorted by pair: walk last step's features alongside.
    std::size_t cached = 0;
    for (const BodyPair& pair : out.pairs) {
        while (cached < c.features.size() && c.features[cached].pair < pair) ++cached;
        const bool known = cached < c.features.size() && c.features[cached].pair == pair;
        shared::PairCache cache = known ? c.features[cached].cache : shared::emptyPairCacheItem();
        const float margin =
            params.continuous
                ? shared::pairMarginItem(bodies.velocities[pair.a], bodies.velocities[pair.b],
                                         c.spin[pair.a], c.spin[pair.b], params.dt)
                : RUBBLE_CONTACT_MARGIN;
        const shared::HullShape& shapeA = c.hulls.shapes[bodies.shapeOf[pair.a]];
        const shared::HullShape& shapeB = c.hulls.shapes[bodies.shapeOf[pair.b]];
        const Shape& fullA = scene.shapes[bodies.shapeOf[pair.a]];
        const Shape& fullB = scene.shapes[bodies.shapeOf[pair.b]];
        // A static mesh collides by its triangles, which may give several manifolds.
        const bool levelA = fullA.level && (bodies.masses[pair.a].flags & RUBBLE_BODY_STATIC);
        const bool levelB = fullB.level && (bodies.masses[pair.b].flags & RUBBLE_BODY_STATIC);
        c.levelManifolds.clear();
        if (levelA || levelB) {
            const std::uint32_t mesh = levelA ? pair.a : pair.b, body = levelA ? pair.b : pair.a;
            const LevelMesh& level = *scene.shapes[bodies.shapeOf[mesh]].level;
            const Shape& other = scene.shapes[bodies.shapeOf[body]];
            const shared::RigidTransform& levelAt = c.transforms[mesh];
            // A body that has hardly moved on the level keeps its manifolds; its triangles stay
            // kept for when it moves on.
            const shared::RigidTransform bodyInLevel =
                recycle ? shared::transformRelative(levelAt, c.transforms[body]) : levelAt;
            const float radius = c.hulls.shapes[bodies.shapeOf[body]].boundingRadius;
            if (recycle && c.levelRecycled.recycle(pair, levelAt, bodyInLevel, radius, margin,
                                                   c.levelManifolds)) {
                c.levelCandidates.carry(pair);
            } else {
                c.levelCandidates.candidates(pair, level, levelQueryBox(levelAt, c.boxes[body]),
                                             c.level.triangles);
                collideLevelTriangles(level, levelAt, other, c.transforms[body],
                                      c.level.triangles, margin, c.level, c.levelManifolds);
                if (recycle)
                    c.levelRecycled.keep(pair, levelAt, bodyInLevel, margin, c.levelManifolds);
            }
            if (levelB)
                for (shared::ContactManifold& m : c.levelManifolds)
                    m.normal = shared::negate4(m.normal);
        } else {
            // Capsules collide by the CPU's own closest features; the rest as the device does.
            const shared::RigidTransform& ta = c.transforms[pair.a];
            const shared::RigidTransform& tb = c.transforms[pair.b];
            if (shapeA.kind == RUBBLE_SHAPE_CAPSULE || shapeB.kind == RUBBLE_SHAPE_CAPSULE) {
                c.levelManifolds.push_back(*collideCapsulePair(fullA, ta, fullB, tb, margin));
            } else if (recycle) {
                shared::RecycledManifold kept = known && haveRecycled
                                                    ? c.recycled[cached]
                                                    : shared::emptyRecycledManifoldItem();
                c.levelManifolds.push_back(shared::collideShapesRecyclingInItem(
                    arrays, shapeA, ta, shapeB, tb, &cache, &kept, margin, buffers));
                if (cache.reusable) c.nextRecycled.push_back(kept);
            } else {
                c.levelManifolds.push_back(shared::collideShapesClippingInItem(
                    arrays, shapeA, ta, shapeB, tb, &cache, margin, buffers));
            }
            if (cache.reusable) c.nextFeatures.push_back({pair, cache});
        }
        for (const shared::ContactManifold& found : c.levelManifolds) {
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
        }
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
    std::swap(c.recycled, c.nextRecycled);
    c.levelCandidates.endStep();
    c.levelRecycled.endStep();
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
    cache_.recycled.clear();
    cache_.nextRecycled.clear();
    cache_.levelCandidates.clear();
    cache_.levelRecycled.clear();
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
