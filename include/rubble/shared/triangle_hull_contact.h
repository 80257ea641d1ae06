// include/rubble/shared/triangle_hull_contact.h: contacts of one static triangle of a level mesh
// with a convex hull placed in the mesh's frame, stage narrowPhase of both pipelines (the sphere
// and capsule contacts and the triangle's own tests are in triangle_contact.h). The arithmetic
// follows glm's operand order, so that both pipelines give the same bits.
#pragma once

#include "rubble/shared/triangle_contact.h"

RUBBLE_SHARED_BEGIN

// A convex hull placed in the mesh's frame by `place` (hull frame to mesh frame). Its placed
// vertices, faces (normal xyz, offset w), edge origins and directions are read from the caller's
// arrays when it has them (the CPU places a hull once per pair) and computed from the hull where
// the pointers are 0 (the device), in the same operations, so that both give the same bits.
// `polygon` and `clipped` hold the hull's largest face plus RUBBLE_TRIANGLE_EXTRA_CONTACTS + 1.
typedef struct PlacedHull {
    Hull hull;
    RigidTransform place;
    Mat3 toHull; // the transpose of place.rotation
    float4 centroid;
    const float4* vertices;
    const float4* faces;
    const float4* edgeOrigins;
    const float4* edgeDirections;
    TaggedPoint* polygon;
    TaggedPoint* clipped;
} PlacedHull;

RUBBLE_FN float4 placedVertexItem(PlacedHull h, uint v) {
    if (h.vertices) return h.vertices[v];
    return transformApply(h.place, h.hull.vertices[v]);
}
RUBBLE_FN float4 placedFaceItem(PlacedHull h, uint f) {
    if (h.faces) return h.faces[f];
    const float4 n = transformRotate(h.place, faceNormalItem(h.hull.faces[f]));
    const float4 corner = placedVertexItem(h, h.hull.edges[h.hull.faceEdge[f]].origin);
    return make4(n.x, n.y, n.z, dot3(n, corner));
}
RUBBLE_FN float4 placedEdgeOriginItem(PlacedHull h, uint e) {
    if (h.edgeOrigins) return h.edgeOrigins[e];
    return transformApply(h.place, h.hull.edgeRecords[e].origin);
}
RUBBLE_FN float4 placedEdgeDirectionItem(PlacedHull h, uint e) {
    if (h.edgeDirections) return h.edgeDirections[e];
    return transformRotate(h.place, h.hull.edgeRecords[e].direction);
}

// Least of dot(u, x) over the placed hull: over its vertices when they are few (a box, a rock),
// by hill climbing in the hull's own frame otherwise.
RUBBLE_FN float placedMinItem(PlacedHull h, float4 u) {
    if (h.hull.vertexCount <= RUBBLE_TRIANGLE_BRUTE_SUPPORT) {
        float low = dot3(u, placedVertexItem(h, 0u));
        for (uint v = 1; v < h.hull.vertexCount; ++v) {
            const float d = dot3(u, placedVertexItem(h, v));
            if (d < low) low = d;
        }
        return low;
    }
    const uint v = supportVertexItem(h.hull, mat3MulVec(h.toHull, negate4(u)), 0u);
    return dot3(u, placedVertexItem(h, v));
}

RUBBLE_FN float triangleMaxItem(MeshTriangle t, float4 u) {
    return max3Item(dot3(u, t.v[0]), dot3(u, t.v[1]), dot3(u, t.v[2]));
}

// Which axis a hull's contact with a triangle comes from.
#define RUBBLE_TRIANGLE_AXIS_FACE 0u
#define RUBBLE_TRIANGLE_AXIS_HULL_FACE 1u
#define RUBBLE_TRIANGLE_AXIS_EDGES 2u

// What made a hull's contact with a triangle, in the low field of its feature id (the triangle's
// index is the high field): the closest points of a hull edge and a triangle edge (the hull
// edge's index << 2 | the triangle edge's side below it), a corner of the triangle clipped to a
// face of the hull (on the triangle), a corner of the hull's face clipped to the triangle's prism
// (on the body); the clipped corner's own tag in the low 12 bits of the last two. Sphere and
// capsule contacts use tags below these (triangle_contact.h).
#define RUBBLE_TRIANGLE_TAG_EDGES 0x4000u
#define RUBBLE_TRIANGLE_TAG_ON_TRIANGLE 0x2000u
#define RUBBLE_TRIANGLE_TAG_ON_BODY 0x1000u
#define RUBBLE_TRIANGLE_TAG_CORNER 0xFFFu

// A convex hull: separating axes (the triangle's normal, the hull's face normals, the cross
// products of the hull's edges with the triangle's boundary edges and its edges convex from the
// hull's side), the least-penetrating axis that normalAllowedItem accepts (faces preferred), then
// the incident face clipped to the triangle, or the triangle to the hull's face, or the edges'
// closest points. Nothing when an axis separates by more than the margin. Internal edges are not
// tested as axes: what touches past them lies over the neighbour, and what this triangle reports
// is clipped to its own prism.
RUBBLE_FN void collideTriangleHullItem(MeshTriangle t, PlacedHull hull, float margin,
                                       ContactBuffer* out) {
    const float side = dot3(t.normal, sub4(hull.centroid, t.v[0])) >= 0.0f ? 1.0f : -1.0f;
    const float4 face = scale4(t.normal, side);

    // The triangle's face.
    uint axis = RUBBLE_TRIANGLE_AXIS_FACE;
    float best = placedMinItem(hull, face) - dot3(face, t.v[0]);
    if (best > margin) return;
    float4 normal = face;
    uint chosenFace = 0u, chosenEdge = 0u, chosenSide = 0u;
    // The hull's faces: u = -n_f, separation = min over the corners of n_f . v - offset.
    for (uint f = 0; f < hull.hull.faceCount; ++f) {
        const float4 plane = placedFaceItem(hull, f);
        const float4 n = faceNormalItem(plane);
        const float separation =
            min3Item(dot3(n, t.v[0]), dot3(n, t.v[1]), dot3(n, t.v[2])) - plane.w;
        if (separation > margin) return;
        if (separation > best + RUBBLE_TRIANGLE_FACE_BIAS &&
            normalAllowedItem(t, side, negate4(n))) {
            best = separation;
            normal = negate4(n);
            axis = RUBBLE_TRIANGLE_AXIS_HULL_FACE;
            chosenFace = f;
        }
    }
    // Edge pairs, each axis turned from the triangle towards the hull, for the triangle's edges
    // that can carry a normal of their own: boundaries and edges convex from this side.
    int edgeMayTouch[3];
    for (uint k = 0; k < 3u; ++k) {
        const uint kind = edgeKindItem(t, k);
        edgeMayTouch[k] = kind == RUBBLE_EDGE_BOUNDARY ||
                          (kind == RUBBLE_EDGE_CONVEX && side > 0.0f) ||
                          (kind == RUBBLE_EDGE_CONCAVE && side < 0.0f);
    }
    const float4 centre = divide4(add4(add4(t.v[0], t.v[1]), t.v[2]), 3.0f);
    const float tolerance = RUBBLE_TRIANGLE_FEATURE_TOLERANCE * longestEdgeItem(t);
    float4 edgeVector[3];
    float edgeLength[3];
    for (uint k = 0; k < 3u; ++k) {
        edgeVector[k] = sub4(t.v[(k + 1u) % 3u], t.v[k]);
        edgeLength[k] = length3(edgeVector[k]);
    }
    for (uint e = 0; e < hull.hull.edgeCount; ++e) {
        const float4 dh = placedEdgeDirectionItem(hull, e);
        const float4 origin = placedEdgeOriginItem(hull, e);
        const float hullEdgeLength = length3(dh);
        for (uint k = 0; k < 3u; ++k) {
            // An internal edge never gives the normal; past it the neighbour's face (or, here,
            // this face clipped to the prism) holds whatever touches.
            if (!edgeMayTouch[k]) continue;
            const float4 a0 = t.v[k], a1 = t.v[(k + 1u) % 3u];
            float4 u = cross3(dh, edgeVector[k]);
            const float len = length3(u);
            if (len <= 1e-5f * hullEdgeLength * edgeLength[k]) continue;
            u = divide4(u, len);
            if (dot3(u, sub4(hull.centroid, centre)) < 0.0f) u = negate4(u);
            // The gap between the two edges' lines along u bounds the separation from above
            // (the hull's least and the triangle's most include the edges' own points): when it
            // can neither separate nor win, the support queries are skipped.
            const float gap = dot3(u, origin) - dot3(u, a0);
            const float winning = best + RUBBLE_TRIANGLE_EDGE_BIAS;
            if (gap <= (winning < margin ? winning : margin)) continue;
            const float low = placedMinItem(hull, u), high = triangleMaxItem(t, u);
            const float separation = low - high;
            if (separation > margin) return;
            if (separation <= best + RUBBLE_TRIANGLE_EDGE_BIAS) continue;
            // A true edge contact: both edges lie on their shapes' extremes along the axis.
            const float originDepth = dot3(u, origin);
            const float endDepth = dot3(u, add4(origin, dh));
            if (originDepth > low + tolerance || endDepth > low + tolerance) continue;
            if (dot3(u, a0) < high - tolerance || dot3(u, a1) < high - tolerance) continue;
            if (!normalAllowedItem(t, side, u)) continue;
            best = separation;
            normal = u;
            axis = RUBBLE_TRIANGLE_AXIS_EDGES;
            chosenEdge = e;
            chosenSide = k;
        }
    }

    const Hull mesh = hull.hull;
    if (axis == RUBBLE_TRIANGLE_AXIS_EDGES) {
        const float4 origin = placedEdgeOriginItem(hull, chosenEdge);
        CapsuleSegment a, b;
        a.p0 = origin;
        a.p1 = add4(origin, placedEdgeDirectionItem(hull, chosenEdge));
        b.p0 = t.v[chosenSide];
        b.p1 = t.v[(chosenSide + 1u) % 3u];
        const CapsuleClosest c = closestSegmentPointsItem(a, b);
        addTriangleContactItem(out, c.onA, normal, best,
                               triangleFeatureItem(t.index, RUBBLE_TRIANGLE_TAG_EDGES |
                                                                (chosenEdge << 2) | chosenSide));
        return;
    }
    TaggedPoint* polygon = hull.polygon;
    TaggedPoint* clipped = hull.clipped;
    uint n = 0;
    if (axis == RUBBLE_TRIANGLE_AXIS_HULL_FACE) {
        // The triangle clipped to the hull's face; its points below the face touch.
        const float4 plane = placedFaceItem(hull, chosenFace);
        const float4 fn = faceNormalItem(plane);
        for (uint k = 0; k < 3u; ++k) {
            polygon[k].position = t.v[k];
            polygon[k].tag = k;
            polygon[k].pad0 = polygon[k].pad1 = polygon[k].pad2 = 0u;
        }
        n = 3u;
        const uint start = mesh.faceEdge[chosenFace];
        uint h = start;
        do {
            const float4 w0 = placedVertexItem(hull, mesh.edges[h].origin);
            const float4 w1 = placedVertexItem(hull, mesh.edges[mesh.edges[h].next].origin);
            n = clipTaggedItem(polygon, n, cross3(sub4(w1, w0), fn), w0, h, clipped);
            TaggedPoint* swap = polygon;
            polygon = clipped;
            clipped = swap;
            h = mesh.edges[h].next;
        } while (h != start && n > 0u);
        for (uint i = 0; i < n; ++i) {
            const float4 q = polygon[i].position;
            const float separation = dot3(fn, q) - plane.w;
            if (separation <= margin)
                addTriangleContactItem(
                    out, sub4(q, scale4(fn, separation)), normal, separation,
                    triangleFeatureItem(t.index,
                                        RUBBLE_TRIANGLE_TAG_ON_TRIANGLE |
                                            (polygon[i].tag & RUBBLE_TRIANGLE_TAG_CORNER)));
        }
        return;
    }
    // The hull's face most against the triangle's normal, clipped to the triangle's prism.
    uint incident = 0u;
    float lowest = dot3(faceNormalItem(placedFaceItem(hull, 0u)), face);
    for (uint f = 1; f < mesh.faceCount; ++f) {
        const float d = dot3(faceNormalItem(placedFaceItem(hull, f)), face);
        if (d < lowest) {
            lowest = d;
            incident = f;
        }
    }
    const uint start = mesh.faceEdge[incident];
    uint h = start;
    do {
        polygon[n].position = placedVertexItem(hull, mesh.edges[h].origin);
        polygon[n].tag = mesh.edges[h].origin & 0x7FFu;
        polygon[n].pad0 = polygon[n].pad1 = polygon[n].pad2 = 0u;
        ++n;
        h = mesh.edges[h].next;
    } while (h != start);
    for (uint k = 0; k < 3u && n > 0u; ++k) {
        n = clipTaggedItem(polygon, n, sideNormalItem(t, k), t.v[k], k, clipped);
        TaggedPoint* swap = polygon;
        polygon = clipped;
        clipped = swap;
    }
    for (uint i = 0; i < n; ++i) {
        const float separation = dot3(face, sub4(polygon[i].position, t.v[0]));
        if (separation <= margin)
            addTriangleContactItem(
                out, polygon[i].position, face, separation,
                triangleFeatureItem(t.index, RUBBLE_TRIANGLE_TAG_ON_BODY |
                                                 (polygon[i].tag & RUBBLE_TRIANGLE_TAG_CORNER)));
    }
}

RUBBLE_SHARED_END
