// host/collision/capsule_contact.cpp: capsule contacts of the CPU narrow phase (stage
// narrowPhase, SatCollision); see capsule_contact.h.
#include "host/collision/capsule_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host/core/math.h"
#include "rubble/shared/narrow_phase.h" // the feature ids of primitive contacts

namespace rubble {
namespace {

using shared::ContactManifold;

// Segments whose directions make an angle with a sine below this touch along their overlap.
constexpr float kParallelSine = 0.05f;
// A face normal this close to the direction between the closest points (cosine) is the face
// a capsule lies on.
constexpr float kFaceCosine = 0.999f;
// An edge axis must separate by this much more than the best face to be chosen (m): faces give
// the steadier manifold.
constexpr float kEdgeTolerance = 1e-3f;

std::uint32_t featureId(std::uint32_t kind, std::uint32_t index) {
    return shared::makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, kind, index);
}

// A point midway between the surfaces: the round shape's at `core - n r` (n the unit normal out
// of the other shape, towards the core) and the other's at `other`; depth -separation.
void addPoint(ContactManifold& m, glm::vec3 core, glm::vec3 other, glm::vec3 n, float radius,
              float separation, std::uint32_t feature) {
    const glm::vec3 position = 0.5f * ((core - n * radius) + other);
    shared::addContactItem(&m, toFloat4(position), -separation, feature);
}

glm::vec3 closestOnSegment(const Segment& s, glm::vec3 p) {
    const glm::vec3 d = s.p1 - s.p0;
    const float dd = glm::dot(d, d);
    const float t = dd > 0.0f ? std::clamp(glm::dot(p - s.p0, d) / dd, 0.0f, 1.0f) : 0.0f;
    return s.p0 + d * t;
}

// A unit vector at right angles to d (d need not be unit; any when d is zero).
glm::vec3 perpendicular(glm::vec3 d) {
    const glm::vec3 other = std::abs(d.x) < 0.57f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
    const glm::vec3 c = glm::cross(d, other);
    const float len = glm::length(c);
    return len > 0.0f ? c / len : glm::vec3(0, 1, 0);
}

// The closest point of the hull's boundary to a point outside it, and the squared distance:
// over the faces the point is above whose polygon its projection falls in, and every edge.
struct HullPoint {
    glm::vec3 point{0.0f};
    float distance2 = std::numeric_limits<float>::max();
};

HullPoint closestOnHull(const HalfEdgeMesh& hull, glm::vec3 c) {
    HullPoint best;
    for (const HalfEdgeFace& f : hull.faces) {
        const float s = glm::dot(f.normal, c) - f.offset;
        if (s <= 0.0f || s * s >= best.distance2) continue;
        const glm::vec3 projected = c - f.normal * s;
        bool inside = true;
        std::uint32_t h = f.edge;
        do {
            const glm::vec3 v0 = hull.vertices[hull.edges[h].origin];
            const glm::vec3 v1 = hull.vertices[hull.edges[hull.edges[h].next].origin];
            if (glm::dot(glm::cross(v1 - v0, f.normal), projected - v0) > 0.0f) inside = false;
            h = hull.edges[h].next;
        } while (inside && h != f.edge);
        if (inside) best = {projected, s * s};
    }
    for (const HalfEdgeEdge& e : hull.edgeRecords) {
        const glm::vec3 q = closestOnSegment(Segment{e.origin, e.origin + e.direction}, c);
        const float d2 = glm::dot(c - q, c - q);
        if (d2 < best.distance2) best = {q, d2};
    }
    return best;
}

// The segment clipped to the prism over hull face f (inside every side plane of the face).
// Returns false when nothing of it is left.
bool clipToFace(const HalfEdgeMesh& hull, std::uint32_t f, Segment& s) {
    const HalfEdgeFace& face = hull.faces[f];
    std::uint32_t h = face.edge;
    do {
        const glm::vec3 v0 = hull.vertices[hull.edges[h].origin];
        const glm::vec3 v1 = hull.vertices[hull.edges[hull.edges[h].next].origin];
        // Out of the face's side: counter-clockwise seen from outside, (v1 - v0) x n is outward.
        const glm::vec3 side = glm::cross(v1 - v0, face.normal);
        const float d0 = glm::dot(side, s.p0 - v0), d1 = glm::dot(side, s.p1 - v0);
        if (d0 > 0.0f && d1 > 0.0f) return false;
        if (d0 > 0.0f) s.p0 = s.p0 + (s.p1 - s.p0) * (d0 / (d0 - d1));
        if (d1 > 0.0f) s.p1 = s.p1 + (s.p0 - s.p1) * (d1 / (d1 - d0));
        h = hull.edges[h].next;
    } while (h != face.edge);
    return true;
}

// The capsule lying on hull face f: the ends of its segment clipped to the face, each within
// the margin. False when the clip leaves nothing.
bool faceContacts(const HalfEdgeMesh& hull, std::uint32_t f, const Segment& s, float radius,
                  float margin, ContactManifold& m) {
    Segment clipped = s;
    if (!clipToFace(hull, f, clipped)) return false;
    const HalfEdgeFace& face = hull.faces[f];
    m.normal = toFloat4(face.normal);
    const glm::vec3 ends[2] = {clipped.p0, clipped.p1};
    const int count = glm::dot(clipped.p1 - clipped.p0, clipped.p1 - clipped.p0) > 0.0f ? 2 : 1;
    for (int k = 0; k < count; ++k) {
        const float above = glm::dot(face.normal, ends[k]) - face.offset;
        const float separation = above - radius;
        if (separation > margin) continue;
        addPoint(m, ends[k], ends[k] - face.normal * above, face.normal, radius, separation,
                 featureId(RUBBLE_PRIMITIVE_FACE, (f << 1) | std::uint32_t(k)));
    }
    return true;
}

} // namespace

SegmentClosest closestSegmentPoints(const Segment& a, const Segment& b) {
    const glm::vec3 d1 = a.p1 - a.p0, d2 = b.p1 - b.p0, r = a.p0 - b.p0;
    const float aa = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    constexpr float kTiny = 1e-12f;
    SegmentClosest c;
    if (aa <= kTiny && e <= kTiny) {
        c.s = c.t = 0.0f;
    } else if (aa <= kTiny) {
        c.s = 0.0f;
        c.t = std::clamp(f / e, 0.0f, 1.0f);
    } else {
        const float cc = glm::dot(d1, r);
        if (e <= kTiny) {
            c.t = 0.0f;
            c.s = std::clamp(-cc / aa, 0.0f, 1.0f);
        } else {
            const float bb = glm::dot(d1, d2);
            const float denom = aa * e - bb * bb;
            // Parallel segments (denom 0): any s; 0 is as good as another.
            c.s = denom > 0.0f ? std::clamp((bb * f - cc * e) / denom, 0.0f, 1.0f) : 0.0f;
            c.t = (bb * c.s + f) / e;
            if (c.t < 0.0f) {
                c.t = 0.0f;
                c.s = std::clamp(-cc / aa, 0.0f, 1.0f);
            } else if (c.t > 1.0f) {
                c.t = 1.0f;
                c.s = std::clamp((bb - cc) / aa, 0.0f, 1.0f);
            }
        }
    }
    c.onA = a.p0 + d1 * c.s;
    c.onB = b.p0 + d2 * c.t;
    return c;
}

Segment capsuleSegment(float halfHeight, const shared::RigidTransform& t) {
    const glm::vec3 centre = toVec3(t.translation);
    const glm::vec3 axis = toVec3(shared::transformRotate(t, shared::vec4(0.0f, halfHeight, 0.0f)));
    return Segment{centre - axis, centre + axis};
}

ContactManifold collidePlaneCapsule(glm::vec3 n, float offset, const Segment& s, float radius,
                                    float margin) {
    ContactManifold m = shared::emptyContactsItem();
    m.normal = toFloat4(n);
    const glm::vec3 ends[2] = {s.p0, s.p1};
    const int count = s.p0 == s.p1 ? 1 : 2;
    for (int k = 0; k < count; ++k) {
        const float above = glm::dot(n, ends[k]) - offset;
        const float separation = above - radius;
        if (separation > margin) continue;
        addPoint(m, ends[k], ends[k] - n * above, n, radius, separation,
                 featureId(RUBBLE_PRIMITIVE_VERTEX, std::uint32_t(k)));
    }
    return m;
}

ContactManifold collideCapsuleSphere(const Segment& s, float radius, glm::vec3 centre,
                                     float sphereRadius, float margin) {
    ContactManifold m = shared::emptyContactsItem();
    const glm::vec3 core = closestOnSegment(s, centre);
    const glm::vec3 d = centre - core;
    const float dist = glm::length(d);
    const float separation = dist - radius - sphereRadius;
    if (separation > margin) return m;
    const glm::vec3 n = dist > 1e-9f ? d / dist : perpendicular(s.p1 - s.p0);
    m.normal = toFloat4(n);
    // Seen from the sphere: its core at the centre, the capsule's surface point the other's.
    addPoint(m, centre, core + n * radius, n, sphereRadius, separation,
             featureId(RUBBLE_PRIMITIVE_WHOLE, 0u));
    return m;
}

ContactManifold collideCapsules(const Segment& a, float ra, const Segment& b, float rb,
                                float margin) {
    ContactManifold m = shared::emptyContactsItem();
    const SegmentClosest c = closestSegmentPoints(a, b);
    const glm::vec3 d = c.onB - c.onA;
    const float dist = glm::length(d);
    const float separation = dist - ra - rb;
    if (separation > margin) return m;
    const glm::vec3 da = a.p1 - a.p0, db = b.p1 - b.p0;
    glm::vec3 n = dist > 1e-9f ? d / dist : perpendicular(da);
    if (dist <= 1e-9f && glm::dot(glm::cross(da, db), glm::cross(da, db)) > 0.0f)
        n = glm::normalize(glm::cross(da, db));
    m.normal = toFloat4(n);
    // Nearly parallel: the two ends of b's overlap with a along a's axis.
    const float aa = glm::dot(da, da), bb = glm::dot(db, db);
    const glm::vec3 cr = glm::cross(da, db);
    if (aa > 0.0f && bb > 0.0f &&
        glm::dot(cr, cr) <= kParallelSine * kParallelSine * aa * bb) {
        const float t0 = glm::dot(b.p0 - a.p0, da) / aa, t1 = glm::dot(b.p1 - a.p0, da) / aa;
        const float lo = std::max(0.0f, std::min(t0, t1)), hi = std::min(1.0f, std::max(t0, t1));
        if (hi > lo) {
            for (const float s : {lo, hi}) {
                const glm::vec3 onA = a.p0 + da * s;
                const glm::vec3 onB = closestOnSegment(b, onA);
                const float sep = glm::dot(onB - onA, n) - ra - rb;
                if (sep > margin) continue;
                // Seen from b: its core at onB, a's surface point the other's.
                addPoint(m, onB, onA + n * ra, n, rb, sep,
                         featureId(RUBBLE_PRIMITIVE_EDGE, s == lo ? 0u : 1u));
            }
            if (m.count > 0) return m;
        }
    }
    addPoint(m, c.onB, c.onA + n * ra, n, rb, separation, featureId(RUBBLE_PRIMITIVE_WHOLE, 0u));
    return m;
}

ContactManifold collideHullCapsule(const HalfEdgeMesh& hull, const Segment& s, float radius,
                                   float margin) {
    ContactManifold m = shared::emptyContactsItem();
    // Face axes: how far the segment's lowest end is above each face.
    std::uint32_t bestFace = 0;
    float faceSeparation = std::numeric_limits<float>::lowest();
    for (std::uint32_t f = 0; f < hull.faces.size(); ++f) {
        const HalfEdgeFace& face = hull.faces[f];
        const float sep =
            std::min(glm::dot(face.normal, s.p0), glm::dot(face.normal, s.p1)) - face.offset;
        if (sep > faceSeparation) {
            faceSeparation = sep;
            bestFace = f;
        }
    }
    // Edge axes: each hull edge crossed with the segment, turned away from the hull's centre.
    const glm::vec3 along = s.p1 - s.p0;
    const glm::vec3 middle = 0.5f * (s.p0 + s.p1);
    std::uint32_t bestEdge = 0;
    float edgeSeparation = std::numeric_limits<float>::lowest();
    glm::vec3 edgeAxis(0.0f);
    for (std::uint32_t k = 0; k < hull.edgeRecords.size(); ++k) {
        const glm::vec3 cr = glm::cross(hull.edgeRecords[k].direction, along);
        const float len = glm::length(cr);
        if (!(len > 1e-6f * glm::length(along) * glm::length(hull.edgeRecords[k].direction)))
            continue;
        glm::vec3 axis = cr / len;
        if (glm::dot(axis, middle - hull.centroid) < 0.0f) axis = -axis;
        const float top = glm::dot(axis, hull.vertices[supportVertex(hull, axis)]);
        const float sep = std::min(glm::dot(axis, s.p0), glm::dot(axis, s.p1)) - top;
        if (sep > edgeSeparation) {
            edgeSeparation = sep;
            bestEdge = k;
            edgeAxis = axis;
        }
    }
    const float coreSeparation = std::max(faceSeparation, edgeSeparation);
    // Every axis bounds the distance from below: clear by more than the margin on one is clear.
    if (coreSeparation - radius > margin) return m;

    if (coreSeparation > 0.0f) {
        // The core is outside the hull: its closest points, from the segment's ends and from the
        // hull's edges (a segment above a face passes over the face's edges or ends over it).
        glm::vec3 onSegment = s.p0, onHull(0.0f);
        float best2 = std::numeric_limits<float>::max();
        for (const glm::vec3 end : {s.p0, s.p1}) {
            const HullPoint h = closestOnHull(hull, end);
            if (h.distance2 < best2) {
                best2 = h.distance2;
                onSegment = end;
                onHull = h.point;
            }
        }
        for (const HalfEdgeEdge& e : hull.edgeRecords) {
            const SegmentClosest c = closestSegmentPoints(s, Segment{e.origin, e.origin + e.direction});
            const float d2 = glm::dot(c.onA - c.onB, c.onA - c.onB);
            if (d2 < best2) {
                best2 = d2;
                onSegment = c.onA;
                onHull = c.onB;
            }
        }
        const float dist = std::sqrt(best2);
        if (dist - radius > margin) return m;
        const glm::vec3 n = dist > 1e-9f ? (onSegment - onHull) / dist : hull.faces[bestFace].normal;
        // Lying on a face: the segment clipped to it.
        std::uint32_t face = bestFace;
        float aligned = glm::dot(hull.faces[face].normal, n);
        for (std::uint32_t f = 0; f < hull.faces.size(); ++f)
            if (const float a = glm::dot(hull.faces[f].normal, n); a > aligned) {
                aligned = a;
                face = f;
            }
        if (aligned > kFaceCosine && faceContacts(hull, face, s, radius, margin, m) && m.count > 0)
            return m;
        m = shared::emptyContactsItem();
        m.normal = toFloat4(n);
        addPoint(m, onSegment, onHull, n, radius, dist - radius,
                 featureId(RUBBLE_PRIMITIVE_VERTEX, 0u));
        return m;
    }

    // The core is inside: out along the axis of least penetration, a face when it is nearly as
    // good as the best edge.
    if (edgeSeparation <= faceSeparation + kEdgeTolerance) {
        if (faceContacts(hull, bestFace, s, radius, margin, m) && m.count > 0) return m;
        // The segment passes the face's prism by: its deeper end goes out through the face.
        m = shared::emptyContactsItem();
        const HalfEdgeFace& face = hull.faces[bestFace];
        m.normal = toFloat4(face.normal);
        const glm::vec3 end =
            glm::dot(face.normal, s.p0) <= glm::dot(face.normal, s.p1) ? s.p0 : s.p1;
        const float above = glm::dot(face.normal, end) - face.offset;
        addPoint(m, end, end - face.normal * above, face.normal, radius, above - radius,
                 featureId(RUBBLE_PRIMITIVE_FACE, bestFace << 1));
        return m;
    }
    const HalfEdgeEdge& e = hull.edgeRecords[bestEdge];
    const SegmentClosest c = closestSegmentPoints(s, Segment{e.origin, e.origin + e.direction});
    m.normal = toFloat4(edgeAxis);
    addPoint(m, c.onA, c.onB, edgeAxis, radius, edgeSeparation - radius,
             featureId(RUBBLE_PRIMITIVE_EDGE, bestEdge));
    return m;
}

namespace {

// A manifold in a shape's frame to the world: points and normal turned and moved.
ContactManifold toWorld(ContactManifold m, const shared::RigidTransform& t) {
    for (std::uint32_t i = 0; i < m.count; ++i) {
        const shared::float4 p = shared::transformApply(t, m.points[i]);
        m.points[i] = shared::make4(p.x, p.y, p.z, m.points[i].w);
    }
    m.normal = shared::transformRotate(t, m.normal);
    return m;
}

ContactManifold flipped(ContactManifold m) {
    m.normal = shared::negate4(m.normal);
    return m;
}

// A capsule `cap` against `other`, normal from the capsule to the other shape.
ContactManifold collideCapsuleWith(const Shape& cap, const shared::RigidTransform& tc,
                                   const Shape& other, const shared::RigidTransform& to,
                                   float margin) {
    const Segment s = capsuleSegment(cap.halfHeight, tc);
    switch (other.type) {
    case ShapeType::Capsule:
        return collideCapsules(s, cap.radius, capsuleSegment(other.halfHeight, to), other.radius,
                               margin);
    case ShapeType::Sphere:
        return collideCapsuleSphere(s, cap.radius, toVec3(to.translation), other.radius, margin);
    case ShapeType::Plane: {
        const shared::float4 n = shared::transformRotate(to, toFloat4(other.normal));
        const float offset = other.offset + shared::dot3(n, to.translation);
        return flipped(collidePlaneCapsule(toVec3(n), offset, s, cap.radius, margin));
    }
    case ShapeType::Box:
    case ShapeType::Convex:
    case ShapeType::Mesh: {
        // The segment in the hull's frame; the contacts back in the world's.
        const Segment local{
            toVec3(shared::transformApplyInverse(to, toFloat4(s.p0))),
            toVec3(shared::transformApplyInverse(to, toFloat4(s.p1)))};
        return flipped(
            toWorld(collideHullCapsule(other.halfEdge, local, cap.radius, margin), to));
    }
    }
    return shared::emptyContactsItem();
}

} // namespace

std::optional<ContactManifold> collideCapsulePair(const Shape& a, const shared::RigidTransform& ta,
                                                  const Shape& b, const shared::RigidTransform& tb,
                                                  float margin) {
    if (a.type == ShapeType::Capsule) return collideCapsuleWith(a, ta, b, tb, margin);
    if (b.type == ShapeType::Capsule) return flipped(collideCapsuleWith(b, tb, a, ta, margin));
    return std::nullopt;
}

} // namespace rubble
