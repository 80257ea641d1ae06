// host/collision/narrow_phase.cpp: CPU stage narrowPhase for one pair: shape-type dispatch and
// the change from a shape's frame to the world. The algorithms are in sat.cpp, hull_contact.cpp
// and primitive_contact.cpp.
#include "host/collision/narrow_phase.h"

#include "host/collision/primitive_contact.h"

namespace rubble {
namespace {

// A contact set from a shape's frame to the world; `flip` turns the normal around when the
// set was made with the pair's shapes swapped.
ContactSet toWorld(const ContactSet& local, const Transform& t, bool flip) {
    ContactSet w = local;
    for (std::uint32_t i = 0; i < w.count; ++i)
        w.points[i].position = t.apply(local.points[i].position);
    w.normal = t.rotate(local.normal);
    if (flip) w.normal = -w.normal;
    return w;
}

struct WorldPlane {
    glm::vec3 normal;
    float offset;
};

// A plane shape at a body's transform: n' = R n, d' = d + dot(n', t).
WorldPlane worldPlane(const Shape& s, const Transform& t) {
    const glm::vec3 n = t.rotate(s.normal);
    return WorldPlane{n, s.offset + glm::dot(n, t.translation)};
}

// A plane against any other shape; the normal points from the plane to the shape.
ContactSet collideWithPlane(const WorldPlane& plane, const Shape& other, const Transform& t,
                            float margin) {
    if (other.type == ShapeType::Sphere)
        return collidePlaneSphere(plane.normal, plane.offset, t.translation, other.radius, margin);
    if (!collidesAsHull(other.type)) return {};
    // The plane in the hull's frame: n_h = R^T n, d_h = d - dot(n, t).
    const glm::vec3 n = t.rotateInverse(plane.normal);
    const float d = plane.offset - glm::dot(plane.normal, t.translation);
    return toWorld(collidePlaneHull(n, d, other.halfEdge, margin), t, false);
}

} // namespace

PairContact collideShapes(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                          float margin) {
    HullPairCache none;
    return collideShapes(a, ta, b, tb, none, margin);
}

PairContact collideShapes(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                          HullPairCache& cache, float margin) {
    PairContact r;
    const bool hullA = collidesAsHull(a.type), hullB = collidesAsHull(b.type);
    if (hullA && hullB) {
        const HullContact hc =
            collideHullsCached(a.halfEdge, b.halfEdge, relative(ta, tb), cache, margin);
        r.contacts = toWorld(hc.contacts, ta, false);
    } else if (a.type == ShapeType::Plane && b.type != ShapeType::Plane) {
        r.contacts = collideWithPlane(worldPlane(a, ta), b, tb, margin);
    } else if (b.type == ShapeType::Plane && a.type != ShapeType::Plane) {
        r.contacts = collideWithPlane(worldPlane(b, tb), a, ta, margin);
        r.contacts.normal = -r.contacts.normal;
    } else if (a.type == ShapeType::Sphere && b.type == ShapeType::Sphere) {
        r.contacts = collideSpheres(ta.translation, a.radius, tb.translation, b.radius, margin);
    } else if (hullA && b.type == ShapeType::Sphere) {
        const ContactSet local =
            collideHullSphere(a.halfEdge, ta.applyInverse(tb.translation), b.radius, margin);
        r.contacts = toWorld(local, ta, false);
    } else if (a.type == ShapeType::Sphere && hullB) {
        const ContactSet local =
            collideHullSphere(b.halfEdge, tb.applyInverse(ta.translation), a.radius, margin);
        r.contacts = toWorld(local, tb, true);
    }
    return r;
}

} // namespace rubble
