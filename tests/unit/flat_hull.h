// tests/unit/flat_hull.h: the shared narrow phase (rubble/shared/sat.h, hull_contact.h,
// primitive_contact.h: what the CPU stage and kernels/sat.cl run) called on half-edge meshes and
// glm poses, its results as glm vectors, for the property tests of the SAT and the manifolds.
#pragma once

#include <algorithm>
#include <vector>

#include <glm/glm.hpp>

#include "host/collision/hull_data.h"
#include "transform.h"
#include "host/core/math.h"
#include "rubble/shared/narrow_phase.h"

namespace rubble::test {

inline constexpr float kContactMargin = RUBBLE_CONTACT_MARGIN;

/// One hull flattened alone (implicitly from its mesh, so that a call may pass the mesh).
struct FlatHull {
    HullData data;
    FlatHull(const HalfEdgeMesh& mesh) { // NOLINT(google-explicit-constructor)
        Shape s;
        s.type = ShapeType::Convex;
        s.halfEdge = mesh;
        data = flattenHulls(std::span<const Shape>(&s, 1));
    }
    shared::Hull hull() const { return shared::hullOfItem(hullArraysOf(data), data.shapes[0]); }
};

/// Clipping buffers for faces of the two hulls.
inline ClipSpace clipSpaceFor(const FlatHull& a, const FlatHull& b) {
    return ClipSpace(std::max(a.data.largestFace, b.data.largestFace));
}

inline shared::RigidTransform rigidOf(const Transform& t) {
    const glm::mat3 rt = glm::transpose(t.rotation); // rows of R as glm columns
    return shared::RigidTransform{shared::Mat3{toFloat4(rt[0]), toFloat4(rt[1]), toFloat4(rt[2])},
                                  toFloat4(t.translation)};
}

inline shared::SatHint noHint() {
    return shared::makeSatHint(RUBBLE_SAT_NONE, 0u, 0u, 0u);
}

/// One contact point and a manifold in glm terms (shared::ContactManifold's fields).
struct LocalContact {
    glm::vec3 position{0.0f};
    float depth = 0.0f;
    std::uint32_t feature = 0;
};
struct ContactSet {
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    std::uint32_t count = 0;
    LocalContact points[RUBBLE_MAX_CONTACT_POINTS];
};
struct HullContact {
    bool separated = false;
    ContactSet contacts;
    shared::SatHint feature;
};

inline ContactSet contactSetOf(const shared::ContactManifold& m) {
    ContactSet c;
    c.normal = toVec3(m.normal);
    c.count = m.count;
    for (std::uint32_t i = 0; i < m.count; ++i)
        c.points[i] = LocalContact{toVec3(m.points[i]), m.points[i].w, m.features[i]};
    return c;
}

inline HullContact hullContactOf(const shared::HullContact& h) {
    return HullContact{h.separated != 0, contactSetOf(h.contacts), h.feature};
}

inline shared::SatResult runSat(const FlatHull& a, const FlatHull& b, const Transform& bInA,
                                float margin = 0.0f, shared::SatHint hint = noHint()) {
    return shared::runSatItem(a.hull(), b.hull(), rigidOf(bInA), margin, hint);
}

inline float separationAlong(const FlatHull& a, const FlatHull& b, const Transform& bInA,
                             glm::vec3 axis) {
    return shared::separationAlongItem(a.hull(), b.hull(), rigidOf(bInA), toFloat4(axis));
}

inline shared::EdgeQuery queryEdgeDirections(const FlatHull& a, const FlatHull& b,
                                             const Transform& bInA) {
    return shared::queryEdgeDirectionsItem(a.hull(), b.hull(), rigidOf(bInA), 3.40282347e+38f);
}

inline HullContact collideHulls(const FlatHull& a, const FlatHull& b, const Transform& bInA,
                                float margin = kContactMargin, shared::SatHint hint = noHint()) {
    ClipSpace clip = clipSpaceFor(a, b);
    return hullContactOf(
        shared::collideHullsItem(a.hull(), b.hull(), rigidOf(bInA), margin, hint, clip.buffers()));
}

inline HullContact collideHullsCached(const FlatHull& a, const FlatHull& b, const Transform& bInA,
                                      shared::PairCache& cache, float margin = kContactMargin) {
    ClipSpace clip = clipSpaceFor(a, b);
    return hullContactOf(shared::collideHullsCachedItem(a.hull(), b.hull(), rigidOf(bInA), &cache,
                                                        margin, clip.buffers()));
}

inline ContactSet collideSpheres(glm::vec3 ca, float ra, glm::vec3 cb, float rb,
                                 float margin = kContactMargin) {
    return contactSetOf(shared::collideSpheresItem(toFloat4(ca), ra, toFloat4(cb), rb, margin));
}

inline ContactSet collideHullSphere(const FlatHull& hull, glm::vec3 centre, float radius,
                                    float margin = kContactMargin) {
    return contactSetOf(
        shared::collideHullSphereItem(hull.hull(), toFloat4(centre), radius, margin));
}

inline ContactSet collidePlaneSphere(glm::vec3 normal, float offset, glm::vec3 centre, float radius,
                                     float margin = kContactMargin) {
    return contactSetOf(
        shared::collidePlaneSphereItem(toFloat4(normal), offset, toFloat4(centre), radius, margin));
}

inline ContactSet collidePlaneHull(glm::vec3 normal, float offset, const FlatHull& hull,
                                   float margin = kContactMargin) {
    return contactSetOf(
        shared::collidePlaneHullItem(toFloat4(normal), offset, hull.hull(), margin));
}

} // namespace rubble::test
