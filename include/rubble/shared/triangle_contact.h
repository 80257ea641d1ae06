// include/rubble/shared/triangle_contact.h: contacts of one static triangle of a level mesh with a
// sphere or a capsule, in the mesh's frame, and the triangle's records and tests that a hull's
// contacts (triangle_hull_contact.h) share, for stage narrowPhase of both pipelines
// (host/collision/level_collision.cpp and kernels/sat.cl gather them per pair through
// shared/level_contact.h). Triangles are two-sided; internal edges (RUBBLE_EDGE_FLAT and
// RUBBLE_EDGE_CONCAVE, and convex ones outside the arc between the two faces' normals) never give
// a contact normal other than the face's, so that bodies slide over the seams of a mesh as over
// one surface. The arithmetic follows glm's operand order, so that both pipelines give the same
// bits.
#pragma once

#include "rubble/shared/capsule_contact.h"

RUBBLE_SHARED_BEGIN

// What lies across a triangle's edge, seen from the side its normal points to
// (host/geometry/level_mesh.h's EdgeKind).
#define RUBBLE_EDGE_BOUNDARY 0u // no neighbour, or more than one: any normal out of the edge
#define RUBBLE_EDGE_FLAT 1u     // a coplanar neighbour: internal, contacts take the face normal
#define RUBBLE_EDGE_CONVEX 2u   // the neighbour bends away: normals between the two faces'
#define RUBBLE_EDGE_CONCAVE 3u  // the neighbour bends towards the normal: internal

// A normal this close to the face's (cosine) is the face's.
#define RUBBLE_TRIANGLE_FACE_COSINE (1.0f - 1e-5f)
// Slack of the arc test of a convex edge (cosine).
#define RUBBLE_TRIANGLE_ARC_SLACK 1e-4f
// Vertices this close to the furthest along a normal (fraction of the longest edge) share it.
#define RUBBLE_TRIANGLE_FEATURE_TOLERANCE 1e-4f
// A hull face must separate by this much more than the triangle's face to be chosen, and an edge
// pair by RUBBLE_TRIANGLE_EDGE_BIAS more (m): faces give the steadier manifolds.
#define RUBBLE_TRIANGLE_FACE_BIAS 5e-4f
#define RUBBLE_TRIANGLE_EDGE_BIAS 1e-3f
// Rounding allowance of the edge pairs' bound (triangle_hull_contact.h's edgePairsMayWinItem), m
// per m of the coordinates' size (plus one m): a few float ulps of both sides.
#define RUBBLE_TRIANGLE_ROUNDING 2e-6f
// Hull edge directions whose axes with a triangle's edges are kept for the edges parallel to
// them (a box's twelve edges have three).
#define RUBBLE_TRIANGLE_KEPT_DIRECTIONS 4u
// Hulls with at most this many vertices find their support by trying every vertex, which is
// faster than hill climbing when the vertices are already placed.
#define RUBBLE_TRIANGLE_BRUTE_SUPPORT 16u
// Closer than this (m) the direction between closest points is no normal.
#define RUBBLE_TRIANGLE_TINY 1e-6f
// Contacts one triangle gives a hull at most, beyond the vertices of the hull's largest face.
#define RUBBLE_TRIANGLE_EXTRA_CONTACTS 3u
// Lowest float (-FLT_MAX).
#define RUBBLE_TRIANGLE_LOWEST (-3.402823466e+38f)

// 128 bytes: one triangle of a level mesh, corners counter-clockwise about `normal`, mesh frame
// (host/geometry/level_mesh.h's LevelTriangle; one per triangle in a device buffer).
typedef struct MeshTriangle {
    float4 v[3];               // corners, m (w = 0)
    float4 normal;             // unit (w = 0)
    float4 neighbourNormal[3]; // across edge k (v[k] to v[k + 1]), wound as this one (w = 0)
    uint edges;                // RUBBLE_EDGE_* of edge k in bits 2k and 2k + 1
    uint index;                // the triangle's index in its level mesh (feature ids)
    uint pad0, pad1;
} MeshTriangle;
RUBBLE_STATIC_ASSERT_SIZE(MeshTriangle, 128);

// 48 bytes, not stored: one contact with a triangle, mesh frame.
typedef struct TriangleContact {
    float4 position; // midway between the surfaces, m (w = 0)
    float4 normal;   // unit, from the triangle to the other body (w = 0)
    float depth;     // penetration along the normal, m (< 0: a gap)
    uint feature;    // the triangle and the point, stable while they touch
    uint pad0, pad1;
} TriangleContact;

// 32 bytes, not stored: a polygon corner being clipped, tagged by the features that made it.
typedef struct TaggedPoint {
    float4 position;
    uint tag;
    uint pad0, pad1, pad2;
} TaggedPoint;

// Contacts appended to the caller's buffer: `count` in use of `capacity`; points past the
// capacity are dropped (the device's buffers are fixed; the host's have room for every point).
typedef struct ContactBuffer {
    TriangleContact* items;
    uint count, capacity;
} ContactBuffer;

// The smallest of three as std::min({x, y, z}) picks it.
RUBBLE_FN float min3Item(float x, float y, float z) {
    float m = x;
    if (y < m) m = y;
    if (z < m) m = z;
    return m;
}

RUBBLE_FN uint edgeKindItem(MeshTriangle t, uint k) {
    return (t.edges >> (2u * k)) & 3u;
}

RUBBLE_FN uint triangleFeatureItem(uint triangle, uint tag) {
    return makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, triangle & 0x7FFFu, tag);
}

RUBBLE_FN float longestEdgeItem(MeshTriangle t) {
    return max3Item(length3(sub4(t.v[1], t.v[0])), length3(sub4(t.v[2], t.v[1])),
                    length3(sub4(t.v[0], t.v[2])));
}

// Whether edge k lets `normal` be a contact normal from `side` of the triangle.
RUBBLE_FN int edgeAllowsItem(MeshTriangle t, float side, uint k, float4 normal) {
    const uint kind = edgeKindItem(t, k);
    if (kind == RUBBLE_EDGE_BOUNDARY) return 1;
    if (kind == RUBBLE_EDGE_FLAT) return 0;
    // A concave edge seen from the back is convex.
    const int convex = (kind == RUBBLE_EDGE_CONVEX) == (side > 0.0f);
    if (!convex) return 0;
    const float4 face = scale4(t.normal, side);
    const float4 other = scale4(t.neighbourNormal[k], side);
    const float4 e = glmNormalize(sub4(t.v[(k + 1u) % 3u], t.v[k]));
    float4 across = sub4(normal, scale4(e, dot3(normal, e)));
    const float len = length3(across);
    if (len < RUBBLE_TRIANGLE_TINY) return 0;
    across = divide4(across, len);
    const float c = dot3(face, other);
    return dot3(across, face) >= c - RUBBLE_TRIANGLE_ARC_SLACK &&
           dot3(across, other) >= c - RUBBLE_TRIANGLE_ARC_SLACK;
}

// True when `normal` (unit, from the triangle outwards) may be a contact normal at the
// triangle's feature furthest along it: the face, a boundary edge, a convex edge within the arc
// between the two faces' normals, or a vertex where one of its edges allows it. `side` (+1 or
// -1) is the side of the triangle the other body is on.
RUBBLE_FN int normalAllowedItem(MeshTriangle t, float side, float4 normal) {
    const float4 face = scale4(t.normal, side);
    if (dot3(normal, face) >= RUBBLE_TRIANGLE_FACE_COSINE) return 1;
    float d[3];
    float top = RUBBLE_TRIANGLE_LOWEST;
    for (uint k = 0; k < 3u; ++k) {
        d[k] = dot3(normal, t.v[k]);
        if (top < d[k]) top = d[k];
    }
    const float tolerance = RUBBLE_TRIANGLE_FEATURE_TOLERANCE * longestEdgeItem(t);
    int at[3];
    int count = 0;
    for (uint k = 0; k < 3u; ++k) {
        at[k] = d[k] >= top - tolerance;
        count += at[k] ? 1 : 0;
    }
    if (count == 3) return dot3(normal, face) > 0.0f;
    if (count == 2) {
        const uint k = !at[0] ? 1u : !at[1] ? 2u : 0u; // the edge from v[k] to v[k + 1]
        return edgeAllowsItem(t, side, k, normal);
    }
    const uint i = at[0] ? 0u : at[1] ? 1u : 2u;
    return edgeAllowsItem(t, side, i, normal) || edgeAllowsItem(t, side, (i + 2u) % 3u, normal);
}

// 32 bytes, not stored: the closest point of a triangle to a point, and the feature it lies on:
// 0..2 vertex k, 3..5 edge k - 3 (from v[k] to v[k + 1]), 6 the face.
typedef struct TrianglePoint {
    float4 point;
    uint feature;
    uint pad0, pad1, pad2;
} TrianglePoint;

RUBBLE_FN TrianglePoint trianglePointItem(float4 point, uint feature) {
    TrianglePoint r;
    r.point = point;
    r.feature = feature;
    r.pad0 = r.pad1 = r.pad2 = 0u;
    return r;
}

// The closest point of the triangle to p (Ericson, "Real-Time Collision Detection", 5.1.5).
RUBBLE_FN TrianglePoint closestOnTriangleItem(MeshTriangle t, float4 p) {
    const float4 a = t.v[0], b = t.v[1], c = t.v[2];
    const float4 ab = sub4(b, a), ac = sub4(c, a), ap = sub4(p, a);
    const float d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return trianglePointItem(a, 0u);
    const float4 bp = sub4(p, b);
    const float d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) return trianglePointItem(b, 1u);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f)
        return trianglePointItem(add4(a, scale4(ab, d1 / (d1 - d3))), 3u);
    const float4 cp = sub4(p, c);
    const float d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) return trianglePointItem(c, 2u);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f)
        return trianglePointItem(add4(a, scale4(ac, d2 / (d2 - d6))), 5u);
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
        return trianglePointItem(add4(b, scale4(sub4(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)))),
                                 4u);
    const float denom = 1.0f / (va + vb + vc);
    return trianglePointItem(add4(add4(a, scale4(ab, vb * denom)), scale4(ac, vc * denom)), 6u);
}

// Appends the contact midway between the surfaces of a body whose surface point is `onBody` and
// a triangle at `separation` from it.
RUBBLE_FN void addTriangleContactItem(ContactBuffer* out, float4 onBody, float4 normal,
                                      float separation, uint feature) {
    if (out->count >= out->capacity) return;
    TriangleContact c;
    c.position = sub4(onBody, scale4(normal, 0.5f * separation));
    c.normal = normal;
    c.depth = -separation;
    c.feature = feature;
    c.pad0 = c.pad1 = 0u;
    out->items[out->count++] = c;
}

// Sutherland-Hodgman: the part of in[0..n) where dot(normal, x - origin) <= 0, into out (room for
// n + 1); returns its corners. A new corner is tagged 0x800 | plane << 8 | the low byte of the
// tag of the edge's start.
RUBBLE_FN uint clipTaggedItem(const TaggedPoint* in, uint n, float4 normal, float4 origin,
                              uint plane, TaggedPoint* out) {
    uint count = 0;
    for (uint i = 0; i < n; ++i) {
        const TaggedPoint a = in[i], b = in[(i + 1u) % n];
        const float da = dot3(normal, sub4(a.position, origin));
        const float db = dot3(normal, sub4(b.position, origin));
        if (da <= 0.0f) out[count++] = a;
        if ((da < 0.0f && db > 0.0f) || (da > 0.0f && db < 0.0f)) {
            TaggedPoint x;
            x.position = add4(a.position, scale4(sub4(b.position, a.position), da / (da - db)));
            x.tag = 0x800u | ((plane & 0x7u) << 8) | (a.tag & 0xFFu);
            x.pad0 = x.pad1 = x.pad2 = 0u;
            out[count++] = x;
        }
    }
    return count;
}

// Outward normal of the triangle's side through edge k (not unit).
RUBBLE_FN float4 sideNormalItem(MeshTriangle t, uint k) {
    return cross3(sub4(t.v[(k + 1u) % 3u], t.v[k]), t.normal);
}

// The segment clipped to the prism over the triangle; 0 when nothing is left.
RUBBLE_FN int clipSegmentToPrismItem(MeshTriangle t, CapsuleSegment* s) {
    for (uint k = 0; k < 3u; ++k) {
        const float4 n = sideNormalItem(t, k);
        const float d0 = dot3(n, sub4(s->p0, t.v[k]));
        const float d1 = dot3(n, sub4(s->p1, t.v[k]));
        if (d0 > 0.0f && d1 > 0.0f) return 0;
        if (d0 > 0.0f) s->p0 = add4(s->p0, scale4(sub4(s->p1, s->p0), d0 / (d0 - d1)));
        if (d1 > 0.0f) s->p1 = add4(s->p1, scale4(sub4(s->p0, s->p1), d1 / (d1 - d0)));
    }
    return 1;
}

// A sphere of radius r at c: one contact within the margin.
RUBBLE_FN void collideTriangleSphereItem(MeshTriangle t, float4 c, float r, float margin,
                                         ContactBuffer* out) {
    const TrianglePoint q = closestOnTriangleItem(t, c);
    const float distance = length3(sub4(c, q.point));
    if (distance > r + margin) return;
    const float above = dot3(t.normal, sub4(c, t.v[0]));
    const float side = above >= 0.0f ? 1.0f : -1.0f;
    const float4 face = scale4(t.normal, side);
    float4 n = q.feature == 6u || distance < RUBBLE_TRIANGLE_TINY
                   ? face
                   : divide4(sub4(c, q.point), distance);
    // Past an internal edge the neighbour's face is the surface: this one's plane continues.
    if (!normalAllowedItem(t, side, n)) n = face;
    const int onFace = dot3(n, face) >= RUBBLE_TRIANGLE_FACE_COSINE;
    const float separation = (onFace ? side * above : distance) - r;
    if (separation > margin) return;
    addTriangleContactItem(out, sub4(c, scale4(n, r)), n, separation,
                           triangleFeatureItem(t.index, 0u));
}

// A capsule (segment s, radius r): the segment's ends clipped to the triangle when it lies on the
// face, otherwise the closest points; each within the margin.
RUBBLE_FN void collideTriangleCapsuleItem(MeshTriangle t, CapsuleSegment s, float r, float margin,
                                          ContactBuffer* out) {
    // The closest points of segment and triangle: where the segment pierces it, its ends
    // against the triangle, or its closest points to the triangle's edges.
    float4 onSegment = s.p0, onTriangle = s.p0;
    float best = RUBBLE_CAPSULE_FAR;
    uint feature = 6u;
    const float s0 = dot3(t.normal, sub4(s.p0, t.v[0])), s1 = dot3(t.normal, sub4(s.p1, t.v[0]));
    if ((s0 <= 0.0f && s1 >= 0.0f) || (s0 >= 0.0f && s1 <= 0.0f)) {
        const float4 x = s0 == s1 ? s.p0 : add4(s.p0, scale4(sub4(s.p1, s.p0), s0 / (s0 - s1)));
        if (closestOnTriangleItem(t, x).feature == 6u) {
            onSegment = onTriangle = x;
            best = 0.0f;
            feature = 6u;
        }
    }
    for (uint k = 0; k < 2u; ++k) {
        const float4 end = k == 0u ? s.p0 : s.p1;
        const TrianglePoint q = closestOnTriangleItem(t, end);
        const float d = length3(sub4(end, q.point));
        if (d < best) {
            onSegment = end;
            onTriangle = q.point;
            best = d;
            feature = q.feature;
        }
    }
    for (uint k = 0; k < 3u; ++k) {
        CapsuleSegment edge;
        edge.p0 = t.v[k];
        edge.p1 = t.v[(k + 1u) % 3u];
        const CapsuleClosest c = closestSegmentPointsItem(s, edge);
        const float d = length3(sub4(c.onA, c.onB));
        if (d < best) {
            onSegment = c.onA;
            onTriangle = c.onB;
            best = d;
            feature = 3u + k;
        }
    }
    if (best > r + margin) return;
    const float4 mid = scale4(add4(s.p0, s.p1), 0.5f);
    const float reference = dot3(t.normal, sub4(onSegment, t.v[0]));
    const float side =
        (fabs(reference) > RUBBLE_TRIANGLE_TINY ? reference : dot3(t.normal, sub4(mid, t.v[0]))) >=
                0.0f
            ? 1.0f
            : -1.0f;
    const float4 face = scale4(t.normal, side);
    float4 n = feature == 6u || best < RUBBLE_TRIANGLE_TINY
                   ? face
                   : divide4(sub4(onSegment, onTriangle), best);
    if (!normalAllowedItem(t, side, n)) n = face;
    if (dot3(n, face) < RUBBLE_TRIANGLE_FACE_COSINE) {
        addTriangleContactItem(out, sub4(onSegment, scale4(n, r)), n, best - r,
                               triangleFeatureItem(t.index, 0u));
        return;
    }
    // Lying on the face: the ends of the segment over the triangle.
    const uint before = out->count;
    CapsuleSegment over = s;
    if (clipSegmentToPrismItem(t, &over)) {
        const uint count = length3(sub4(over.p1, over.p0)) > RUBBLE_TRIANGLE_TINY ? 2u : 1u;
        for (uint k = 0; k < count; ++k) {
            const float4 end = k == 0u ? over.p0 : over.p1;
            const float separation = dot3(face, sub4(end, t.v[0])) - r;
            if (separation <= margin)
                addTriangleContactItem(out, sub4(end, scale4(face, r)), face, separation,
                                       triangleFeatureItem(t.index, 1u + k));
        }
    }
    if (out->count > before) return;
    const float separation = dot3(face, sub4(onSegment, t.v[0])) - r;
    if (separation <= margin)
        addTriangleContactItem(out, sub4(onSegment, scale4(face, r)), face, separation,
                               triangleFeatureItem(t.index, 0u));
}

RUBBLE_SHARED_END
