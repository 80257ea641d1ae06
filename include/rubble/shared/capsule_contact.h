// include/rubble/shared/capsule_contact.h: capsule contacts of stage narrowPhase, per pair:
// capsules against planes, spheres, capsules and convex hulls (closest points of segments,
// Ericson 5.1.9; separating axes of a hull against the segment; the segment clipped to a face it
// lies on). kernels/sat.cl runs them through narrow_phase.h; the CPU reference is
// host/collision/capsule_contact.cpp, whose steps these repeat in glm's operand order.
#pragma once

// hull_contact.h brings clip.h and sat.h, which primitive_contact.h reads.
#include "rubble/shared/hull_contact.h"
#include "rubble/shared/primitive_contact.h"

RUBBLE_SHARED_BEGIN

// Segments whose directions make an angle with a sine below this touch along their overlap.
#define RUBBLE_CAPSULE_PARALLEL_SINE 0.05f
// A face normal this close to the direction between the closest points (cosine) is the face a
// capsule lies on.
#define RUBBLE_CAPSULE_FACE_COSINE 0.999f
// An edge axis must separate by this much more than the best face to be chosen, m.
#define RUBBLE_CAPSULE_EDGE_TOLERANCE 1e-3f
// Larger than any squared distance the narrow phase meets, m^2 (FLT_MAX).
#define RUBBLE_CAPSULE_FAR 3.402823466e+38f

// 32 bytes, not stored: a capsule's core, the segment from p0 to p1, m.
typedef struct CapsuleSegment {
    float4 p0, p1;
} CapsuleSegment;

// 48 bytes, not stored: the closest points of two segments, at s along a and t along b.
typedef struct CapsuleClosest {
    float4 onA, onB;
    float s, t, pad0, pad1;
} CapsuleClosest;

RUBBLE_FN uint capsuleFeatureItem(uint kind, uint index) {
    return makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, kind, index);
}

// A point midway between the surfaces: the round shape's at core - n r (n the unit normal out of
// the other shape, towards the core) and the other's at `other`; depth -separation.
RUBBLE_FN void addCapsulePointItem(ContactManifold* m, float4 core, float4 other, float4 n,
                                   float radius, float separation, uint feature) {
    const float4 position = scale4(add4(sub4(core, scale4(n, radius)), other), 0.5f);
    addContactItem(m, position, -separation, feature);
}

RUBBLE_FN float4 closestOnSegmentItem(CapsuleSegment s, float4 p) {
    const float4 d = sub4(s.p1, s.p0);
    const float dd = dot3(d, d);
    const float t = dd > 0.0f ? clampItem(dot3(sub4(p, s.p0), d) / dd, 0.0f, 1.0f) : 0.0f;
    return vec4(s.p0.x + d.x * t, s.p0.y + d.y * t, s.p0.z + d.z * t);
}

// A unit vector at right angles to d (any when d is zero).
RUBBLE_FN float4 capsulePerpendicularItem(float4 d) {
    const float4 other = fabs(d.x) < 0.57f ? vec4(1.0f, 0.0f, 0.0f) : vec4(0.0f, 0.0f, 1.0f);
    const float4 c = cross3(d, other);
    const float len = length3(c);
    return len > 0.0f ? divide4(c, len) : vec4(0.0f, 1.0f, 0.0f);
}

// Closest points of segments a and b (Ericson, "Real-Time Collision Detection", 5.1.9); for
// parallel segments, one pair of the closest.
RUBBLE_FN CapsuleClosest closestSegmentPointsItem(CapsuleSegment a, CapsuleSegment b) {
    const float4 d1 = sub4(a.p1, a.p0), d2 = sub4(b.p1, b.p0), r = sub4(a.p0, b.p0);
    const float aa = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r);
    const float tiny = 1e-12f;
    CapsuleClosest c;
    c.s = 0.0f;
    c.t = 0.0f;
    c.pad0 = c.pad1 = 0.0f;
    if (aa <= tiny && e <= tiny) {
        c.s = c.t = 0.0f;
    } else if (aa <= tiny) {
        c.s = 0.0f;
        c.t = clampItem(f / e, 0.0f, 1.0f);
    } else {
        const float cc = dot3(d1, r);
        if (e <= tiny) {
            c.t = 0.0f;
            c.s = clampItem(-cc / aa, 0.0f, 1.0f);
        } else {
            const float bb = dot3(d1, d2);
            const float denom = aa * e - bb * bb;
            c.s = denom > 0.0f ? clampItem((bb * f - cc * e) / denom, 0.0f, 1.0f) : 0.0f;
            c.t = (bb * c.s + f) / e;
            if (c.t < 0.0f) {
                c.t = 0.0f;
                c.s = clampItem(-cc / aa, 0.0f, 1.0f);
            } else if (c.t > 1.0f) {
                c.t = 1.0f;
                c.s = clampItem((bb - cc) / aa, 0.0f, 1.0f);
            }
        }
    }
    c.onA = add4(vec4(a.p0.x, a.p0.y, a.p0.z), scale4(vec4(d1.x, d1.y, d1.z), c.s));
    c.onB = add4(vec4(b.p0.x, b.p0.y, b.p0.z), scale4(vec4(d2.x, d2.y, d2.z), c.t));
    return c;
}

// The capsule's segment (half height h along its local y) at a body's transform.
RUBBLE_FN CapsuleSegment capsuleSegmentItem(float halfHeight, RigidTransform t) {
    const float4 centre = vec4(t.translation.x, t.translation.y, t.translation.z);
    const float4 axis = transformRotate(t, vec4(0.0f, halfHeight, 0.0f));
    CapsuleSegment s;
    s.p0 = sub4(centre, axis);
    s.p1 = add4(centre, axis);
    return s;
}

// A plane (solid below dot(n, x) = offset) and a capsule: one point per end of the segment
// within the margin; the normal is the plane's.
RUBBLE_FN ContactManifold collidePlaneCapsuleItem(float4 n, float offset, CapsuleSegment s,
                                                  float radius, float margin) {
    ContactManifold m = emptyContactsItem();
    m.normal = vec4(n.x, n.y, n.z);
    const int same = s.p0.x == s.p1.x && s.p0.y == s.p1.y && s.p0.z == s.p1.z;
    const uint count = same ? 1u : 2u;
    for (uint k = 0; k < count; ++k) {
        const float4 end = k == 0u ? s.p0 : s.p1;
        const float above = dot3(n, end) - offset;
        const float separation = above - radius;
        if (separation > margin) continue;
        addCapsulePointItem(&m, end, sub4(end, scale4(n, above)), n, radius, separation,
                            capsuleFeatureItem(RUBBLE_PRIMITIVE_VERTEX, k));
    }
    return m;
}

// A capsule and a sphere; the normal points from the capsule to the sphere.
RUBBLE_FN ContactManifold collideCapsuleSphereItem(CapsuleSegment s, float radius, float4 centre,
                                                   float sphereRadius, float margin) {
    ContactManifold m = emptyContactsItem();
    const float4 c = vec4(centre.x, centre.y, centre.z);
    const float4 core = closestOnSegmentItem(s, c);
    const float4 d = sub4(c, core);
    const float dist = length3(d);
    const float separation = dist - radius - sphereRadius;
    if (separation > margin) return m;
    const float4 n = dist > 1e-9f ? divide4(d, dist) : capsulePerpendicularItem(sub4(s.p1, s.p0));
    m.normal = n;
    // Seen from the sphere: its core at the centre, the capsule's surface point the other's.
    addCapsulePointItem(&m, c, add4(core, scale4(n, radius)), n, sphereRadius, separation,
                        capsuleFeatureItem(RUBBLE_PRIMITIVE_WHOLE, 0u));
    return m;
}

// Two capsules; the normal points from a to b. Nearly parallel segments that overlap along their
// length touch at the two ends of the overlap.
RUBBLE_FN ContactManifold collideCapsulesItem(CapsuleSegment a, float ra, CapsuleSegment b,
                                              float rb, float margin) {
    ContactManifold m = emptyContactsItem();
    const CapsuleClosest c = closestSegmentPointsItem(a, b);
    const float4 d = sub4(c.onB, c.onA);
    const float dist = length3(d);
    const float separation = dist - ra - rb;
    if (separation > margin) return m;
    const float4 da = sub4(a.p1, a.p0), db = sub4(b.p1, b.p0);
    const float4 cr = cross3(da, db);
    float4 n = dist > 1e-9f ? divide4(d, dist) : capsulePerpendicularItem(da);
    if (dist <= 1e-9f && dot3(cr, cr) > 0.0f) n = glmNormalize(cr);
    m.normal = n;
    // Nearly parallel: the two ends of b's overlap with a along a's axis.
    const float aa = dot3(da, da), bb = dot3(db, db);
    const float sine2 = RUBBLE_CAPSULE_PARALLEL_SINE * RUBBLE_CAPSULE_PARALLEL_SINE;
    if (aa > 0.0f && bb > 0.0f && dot3(cr, cr) <= sine2 * aa * bb) {
        const float t0 = dot3(sub4(b.p0, a.p0), da) / aa, t1 = dot3(sub4(b.p1, a.p0), da) / aa;
        const float lo = fmax(0.0f, fmin(t0, t1)), hi = fmin(1.0f, fmax(t0, t1));
        if (hi > lo) {
            for (uint k = 0; k < 2u; ++k) {
                const float s = k == 0u ? lo : hi;
                const float4 onA = add4(vec4(a.p0.x, a.p0.y, a.p0.z), scale4(da, s));
                const float4 onB = closestOnSegmentItem(b, onA);
                const float sep = dot3(sub4(onB, onA), n) - ra - rb;
                if (sep > margin) continue;
                // Seen from b: its core at onB, a's surface point the other's.
                addCapsulePointItem(&m, onB, add4(onA, scale4(n, ra)), n, rb, sep,
                                    capsuleFeatureItem(RUBBLE_PRIMITIVE_EDGE, k));
            }
            if (m.count > 0u) return m;
        }
    }
    addCapsulePointItem(&m, c.onB, add4(c.onA, scale4(n, ra)), n, rb, separation,
                        capsuleFeatureItem(RUBBLE_PRIMITIVE_WHOLE, 0u));
    return m;
}

// Hull face f's edge from half-edge h: its two vertices.
RUBBLE_FN float4 halfEdgeStartItem(Hull hull, uint h) {
    return hull.vertices[hull.edges[h].origin];
}
RUBBLE_FN float4 halfEdgeEndItem(Hull hull, uint h) {
    return hull.vertices[hull.edges[hull.edges[h].next].origin];
}

// The closest point of the hull's boundary to a point c outside it (xyz) and the squared
// distance (w): over the faces c is above whose polygon its projection falls in, and every edge.
RUBBLE_FN float4 closestOnHullItem(Hull hull, float4 c) {
    float4 best = make4(0.0f, 0.0f, 0.0f, RUBBLE_CAPSULE_FAR);
    for (uint f = 0; f < hull.faceCount; ++f) {
        const float4 face = hull.faces[f];
        const float4 normal = vec4(face.x, face.y, face.z);
        const float s = dot3(normal, c) - face.w;
        if (s <= 0.0f || s * s >= best.w) continue;
        const float4 projected = sub4(c, scale4(normal, s));
        int inside = 1;
        uint h = hull.faceEdge[f];
        do {
            const float4 v0 = halfEdgeStartItem(hull, h), v1 = halfEdgeEndItem(hull, h);
            if (dot3(cross3(sub4(v1, v0), normal), sub4(projected, v0)) > 0.0f) inside = 0;
            h = hull.edges[h].next;
        } while (inside && h != hull.faceEdge[f]);
        if (inside) best = make4(projected.x, projected.y, projected.z, s * s);
    }
    for (uint k = 0; k < hull.edgeCount; ++k) {
        const HullEdge e = hull.edgeRecords[k];
        CapsuleSegment edge;
        edge.p0 = e.origin;
        edge.p1 = add4(e.origin, e.direction);
        const float4 q = closestOnSegmentItem(edge, c);
        const float d2 = dot3(sub4(c, q), sub4(c, q));
        if (d2 < best.w) best = make4(q.x, q.y, q.z, d2);
    }
    return best;
}

// The segment clipped to the prism over hull face f (inside every side plane of the face), into
// *s; 0 when nothing of it is left.
RUBBLE_FN int clipSegmentToFaceItem(Hull hull, uint f, CapsuleSegment* s) {
    const float4 face = hull.faces[f];
    const float4 normal = vec4(face.x, face.y, face.z);
    uint h = hull.faceEdge[f];
    do {
        const float4 v0 = halfEdgeStartItem(hull, h), v1 = halfEdgeEndItem(hull, h);
        // Out of the face's side: counter-clockwise seen from outside, (v1 - v0) x n is outward.
        const float4 side = cross3(sub4(v1, v0), normal);
        const float d0 = dot3(side, sub4(s->p0, v0)), d1 = dot3(side, sub4(s->p1, v0));
        if (d0 > 0.0f && d1 > 0.0f) return 0;
        if (d0 > 0.0f) s->p0 = add4(s->p0, scale4(sub4(s->p1, s->p0), d0 / (d0 - d1)));
        if (d1 > 0.0f) s->p1 = add4(s->p1, scale4(sub4(s->p0, s->p1), d1 / (d1 - d0)));
        h = hull.edges[h].next;
    } while (h != hull.faceEdge[f]);
    return 1;
}

// The capsule lying on hull face f: the ends of its segment clipped to the face, each within the
// margin, into *m. 0 when the clip leaves nothing.
RUBBLE_FN int capsuleFaceContactsItem(Hull hull, uint f, CapsuleSegment s, float radius,
                                      float margin, ContactManifold* m) {
    CapsuleSegment clipped = s;
    if (!clipSegmentToFaceItem(hull, f, &clipped)) return 0;
    const float4 face = hull.faces[f];
    const float4 normal = vec4(face.x, face.y, face.z);
    m->normal = normal;
    const float4 along = sub4(clipped.p1, clipped.p0);
    const uint count = dot3(along, along) > 0.0f ? 2u : 1u;
    for (uint k = 0; k < count; ++k) {
        const float4 end = k == 0u ? clipped.p0 : clipped.p1;
        const float above = dot3(normal, end) - face.w;
        const float separation = above - radius;
        if (separation > margin) continue;
        addCapsulePointItem(m, end, sub4(end, scale4(normal, above)), normal, radius, separation,
                            capsuleFeatureItem(RUBBLE_PRIMITIVE_FACE, (f << 1) | k));
    }
    return 1;
}

// A convex hull and a capsule whose segment is in the hull's frame; the result is in the hull's
// frame, normal from the hull to the capsule. The separating axes are the hull's face normals and
// the cross products of its edges with the segment; a capsule whose closest feature is a face
// (lying on it) touches at the segment clipped to that face, up to two points, otherwise at one.
RUBBLE_FN ContactManifold collideHullCapsuleItem(Hull hull, CapsuleSegment s, float radius,
                                                 float margin) {
    ContactManifold m = emptyContactsItem();
    // Face axes: how far the segment's lowest end is above each face.
    uint bestFace = 0u;
    float faceSeparation = -RUBBLE_CAPSULE_FAR;
    for (uint f = 0; f < hull.faceCount; ++f) {
        const float4 face = hull.faces[f];
        const float4 normal = vec4(face.x, face.y, face.z);
        const float sep = fmin(dot3(normal, s.p0), dot3(normal, s.p1)) - face.w;
        if (sep > faceSeparation) {
            faceSeparation = sep;
            bestFace = f;
        }
    }
    // Edge axes: each hull edge crossed with the segment, turned away from the hull's centre.
    const float4 along = sub4(s.p1, s.p0);
    const float4 middle = scale4(add4(s.p0, s.p1), 0.5f);
    uint bestEdge = 0u;
    float edgeSeparation = -RUBBLE_CAPSULE_FAR;
    float4 edgeAxis = vec4(0.0f, 0.0f, 0.0f);
    for (uint k = 0; k < hull.edgeCount; ++k) {
        const float4 direction = hull.edgeRecords[k].direction;
        const float4 cr = cross3(direction, along);
        const float len = length3(cr);
        if (!(len > 1e-6f * length3(along) * length3(direction))) continue;
        float4 axis = divide4(cr, len);
        if (dot3(axis, sub4(middle, hull.centroid)) < 0.0f) axis = negate4(axis);
        const float top = dot3(axis, hull.vertices[supportVertexItem(hull, axis, 0u)]);
        const float sep = fmin(dot3(axis, s.p0), dot3(axis, s.p1)) - top;
        if (sep > edgeSeparation) {
            edgeSeparation = sep;
            bestEdge = k;
            edgeAxis = axis;
        }
    }
    const float coreSeparation = fmax(faceSeparation, edgeSeparation);
    // Every axis bounds the distance from below: clear by more than the margin on one is clear.
    if (coreSeparation - radius > margin) return m;

    if (coreSeparation > 0.0f) {
        // The core is outside the hull: its closest points, from the segment's ends and from the
        // hull's edges.
        float4 onSegment = s.p0, onHull = vec4(0.0f, 0.0f, 0.0f);
        float best2 = RUBBLE_CAPSULE_FAR;
        for (uint k = 0; k < 2u; ++k) {
            const float4 end = k == 0u ? s.p0 : s.p1;
            const float4 h = closestOnHullItem(hull, end);
            if (h.w < best2) {
                best2 = h.w;
                onSegment = end;
                onHull = vec4(h.x, h.y, h.z);
            }
        }
        for (uint k = 0; k < hull.edgeCount; ++k) {
            const HullEdge e = hull.edgeRecords[k];
            CapsuleSegment edge;
            edge.p0 = e.origin;
            edge.p1 = add4(e.origin, e.direction);
            const CapsuleClosest c = closestSegmentPointsItem(s, edge);
            const float d2 = dot3(sub4(c.onA, c.onB), sub4(c.onA, c.onB));
            if (d2 < best2) {
                best2 = d2;
                onSegment = c.onA;
                onHull = c.onB;
            }
        }
        const float dist = sqrt(best2);
        if (dist - radius > margin) return m;
        const float4 faceNormal = hull.faces[bestFace];
        const float4 n = dist > 1e-9f ? divide4(sub4(onSegment, onHull), dist)
                                      : vec4(faceNormal.x, faceNormal.y, faceNormal.z);
        // Lying on a face: the segment clipped to it.
        uint face = bestFace;
        float aligned = dot3(hull.faces[face], n);
        for (uint f = 0; f < hull.faceCount; ++f) {
            const float a = dot3(hull.faces[f], n);
            if (a > aligned) {
                aligned = a;
                face = f;
            }
        }
        if (aligned > RUBBLE_CAPSULE_FACE_COSINE &&
            capsuleFaceContactsItem(hull, face, s, radius, margin, &m) && m.count > 0u)
            return m;
        m = emptyContactsItem();
        m.normal = n;
        addCapsulePointItem(&m, onSegment, onHull, n, radius, dist - radius,
                            capsuleFeatureItem(RUBBLE_PRIMITIVE_VERTEX, 0u));
        return m;
    }

    // The core is inside: out along the axis of least penetration, a face when it is nearly as
    // good as the best edge.
    if (edgeSeparation <= faceSeparation + RUBBLE_CAPSULE_EDGE_TOLERANCE) {
        if (capsuleFaceContactsItem(hull, bestFace, s, radius, margin, &m) && m.count > 0u)
            return m;
        // The segment passes the face's prism by: its deeper end goes out through the face.
        m = emptyContactsItem();
        const float4 face = hull.faces[bestFace];
        const float4 normal = vec4(face.x, face.y, face.z);
        m.normal = normal;
        const float4 end = dot3(normal, s.p0) <= dot3(normal, s.p1) ? s.p0 : s.p1;
        const float above = dot3(normal, end) - face.w;
        addCapsulePointItem(&m, end, sub4(end, scale4(normal, above)), normal, radius,
                            above - radius,
                            capsuleFeatureItem(RUBBLE_PRIMITIVE_FACE, bestFace << 1));
        return m;
    }
    const HullEdge e = hull.edgeRecords[bestEdge];
    CapsuleSegment edge;
    edge.p0 = e.origin;
    edge.p1 = add4(e.origin, e.direction);
    const CapsuleClosest c = closestSegmentPointsItem(s, edge);
    m.normal = edgeAxis;
    addCapsulePointItem(&m, c.onA, c.onB, edgeAxis, radius, edgeSeparation - radius,
                        capsuleFeatureItem(RUBBLE_PRIMITIVE_EDGE, bestEdge));
    return m;
}

RUBBLE_SHARED_END
