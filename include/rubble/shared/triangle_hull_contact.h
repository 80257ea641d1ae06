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

// Whether an edge pair's axis may separate the triangle from the hull by more than
// min(best + RUBBLE_TRIANGLE_EDGE_BIAS, margin), as it must to be chosen (or to end the test).
// No axis separates the shapes by more than the distance between a point of each: a corner of the
// triangle inside the hull bounds every axis by its excess over the face planes (minus its depth,
// as the hull holds the ball of that radius about it), one outside by its excess when its
// projection onto that face's plane lies in the hull. `excess` and `excessFace` hold each
// corner's largest excess and its face. The bound is given RUBBLE_TRIANGLE_ROUNDING (relative to
// the coordinates' size) for the rounding of both it and the axes' separations, so that the edge
// pairs it leaves out would not have been chosen.
RUBBLE_FN int edgePairsMayWinItem(MeshTriangle t, PlacedHull hull, float best, float margin,
                                  const float* excess, const uint* excessFace) {
    const float winning = best + RUBBLE_TRIANGLE_EDGE_BIAS;
    const float threshold = winning < margin ? winning : margin;
    float size = fabs(hull.centroid.x) + fabs(hull.centroid.y) + fabs(hull.centroid.z);
    for (uint k = 0; k < 3u; ++k) {
        const float s = fabs(t.v[k].x) + fabs(t.v[k].y) + fabs(t.v[k].z);
        if (s > size) size = s;
    }
    const float limit = threshold - RUBBLE_TRIANGLE_ROUNDING * (1.0f + size);
    for (uint k = 0; k < 3u; ++k) {
        if (excess[k] > limit) continue;
        if (excess[k] <= 0.0f) return 0;
        const float4 n = faceNormalItem(placedFaceItem(hull, excessFace[k]));
        const float4 q = sub4(t.v[k], scale4(n, excess[k]));
        int inside = 1;
        for (uint f = 0; f < hull.hull.faceCount && inside; ++f) {
            const float4 plane = placedFaceItem(hull, f);
            inside = f == excessFace[k] || dot3(faceNormalItem(plane), q) - plane.w <= 0.0f;
        }
        if (inside) return 0;
    }
    return 1;
}

// Whether a and b have the same bits in x, y and z (equal, and zeros of the same sign).
RUBBLE_FN int sameBitsItem(float a, float b) {
    return a == b && (a != 0.0f || 1.0f / a == 1.0f / b);
}
RUBBLE_FN int sameBits3Item(float4 a, float4 b) {
    return sameBitsItem(a.x, b.x) && sameBitsItem(a.y, b.y) && sameBitsItem(a.z, b.z);
}

// What triangleEdgeAxisItem found: no axis (the edges are parallel), a component of the cross
// product that is 0, a test of the axis's side that gave 0.
#define RUBBLE_EDGE_AXIS_NONE 1u
#define RUBBLE_EDGE_AXIS_ZERO_PART 2u
#define RUBBLE_EDGE_AXIS_SIDE_ZERO 4u

// The axis of a hull edge of direction `dh` and a triangle edge `edge` (of length `edgeLength`):
// their unit cross product turned towards `toHull` (the hull's centroid from the triangle's),
// into `axis`; flags as above.
RUBBLE_FN uint triangleEdgeAxisItem(float4 dh, float4 edge, float edgeLength, float4 toHull,
                                    float4* axis) {
    float4 u = cross3(dh, edge);
    const float len = length3(u);
    *axis = vec4(0.0f, 0.0f, 0.0f);
    if (len <= 1e-5f * length3(dh) * edgeLength) return RUBBLE_EDGE_AXIS_NONE;
    uint flags = u.x == 0.0f || u.y == 0.0f || u.z == 0.0f ? RUBBLE_EDGE_AXIS_ZERO_PART : 0u;
    u = divide4(u, len);
    const float side = dot3(u, toHull);
    if (side == 0.0f) flags |= RUBBLE_EDGE_AXIS_SIDE_ZERO;
    *axis = side < 0.0f ? negate4(u) : u;
    return flags;
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
    // The hull's faces: u = -n_f, separation = min over the corners of n_f . v - offset. Each
    // corner's largest excess over the face planes, and its face, bound the edge pairs below.
    float excess[3] = {RUBBLE_TRIANGLE_LOWEST, RUBBLE_TRIANGLE_LOWEST, RUBBLE_TRIANGLE_LOWEST};
    uint excessFace[3] = {0u, 0u, 0u};
    for (uint f = 0; f < hull.hull.faceCount; ++f) {
        const float4 plane = placedFaceItem(hull, f);
        const float4 n = faceNormalItem(plane);
        const float separation =
            min3Item(dot3(n, t.v[0]), dot3(n, t.v[1]), dot3(n, t.v[2])) - plane.w;
        if (separation > margin) return;
        for (uint k = 0; k < 3u; ++k) {
            const float over = dot3(n, t.v[k]) - plane.w;
            if (over > excess[k]) {
                excess[k] = over;
                excessFace[k] = f;
            }
        }
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
    const uint edgeCount = (edgeMayTouch[0] || edgeMayTouch[1] || edgeMayTouch[2]) &&
                                   edgePairsMayWinItem(t, hull, best, margin, excess, excessFace)
                               ? hull.hull.edgeCount
                               : 0u;
    float4 centre = t.v[0], edgeVector[3];
    float tolerance = 0.0f, edgeLength[3];
    if (edgeCount > 0u) {
        centre = divide4(add4(add4(t.v[0], t.v[1]), t.v[2]), 3.0f);
        tolerance = RUBBLE_TRIANGLE_FEATURE_TOLERANCE * longestEdgeItem(t);
        for (uint k = 0; k < 3u; ++k) {
            edgeVector[k] = sub4(t.v[(k + 1u) % 3u], t.v[k]);
            edgeLength[k] = length3(edgeVector[k]);
        }
    }
    // The axes of the hull edges' first few directions, kept for the edges that share one.
    float4 keptDirection[RUBBLE_TRIANGLE_KEPT_DIRECTIONS];
    float4 keptAxis[RUBBLE_TRIANGLE_KEPT_DIRECTIONS][3];
    uint keptFlags[RUBBLE_TRIANGLE_KEPT_DIRECTIONS][3];
    uint kept = 0u;
    const float4 toHull = sub4(hull.centroid, centre);
    for (uint e = 0; e < edgeCount; ++e) {
        const float4 dh = placedEdgeDirectionItem(hull, e);
        const float4 origin = placedEdgeOriginItem(hull, e);
        uint slot = kept;
        int opposite = 0;
        for (uint s = 0; s < kept && slot == kept; ++s) {
            if (sameBits3Item(keptDirection[s], dh)) {
                slot = s;
            } else if (sameBits3Item(keptDirection[s], negate4(dh))) {
                slot = s;
                opposite = 1;
            }
        }
        float4 axes[3];
        uint flags[3];
        if (slot < kept) {
            for (uint k = 0; k < 3u; ++k) {
                axes[k] = keptAxis[slot][k];
                flags[k] = keptFlags[slot][k];
                if (!opposite || (flags[k] & RUBBLE_EDGE_AXIS_NONE)) continue;
                // The opposite direction's axis before turning is the negation, exactly, when
                // no component of the cross product is 0; it turns the other way unless the
                // test of its side gave 0.
                if (flags[k] & RUBBLE_EDGE_AXIS_ZERO_PART)
                    flags[k] =
                        triangleEdgeAxisItem(dh, edgeVector[k], edgeLength[k], toHull, &axes[k]);
                else if (flags[k] & RUBBLE_EDGE_AXIS_SIDE_ZERO)
                    axes[k] = negate4(axes[k]);
            }
        } else {
            for (uint k = 0; k < 3u; ++k) {
                axes[k] = vec4(0.0f, 0.0f, 0.0f);
                flags[k] = edgeMayTouch[k] ? triangleEdgeAxisItem(dh, edgeVector[k], edgeLength[k],
                                                                  toHull, &axes[k])
                                           : RUBBLE_EDGE_AXIS_NONE;
            }
            if (kept < RUBBLE_TRIANGLE_KEPT_DIRECTIONS) {
                keptDirection[kept] = dh;
                for (uint k = 0; k < 3u; ++k) {
                    keptAxis[kept][k] = axes[k];
                    keptFlags[kept][k] = flags[k];
                }
                ++kept;
            }
        }
        for (uint k = 0; k < 3u; ++k) {
            // An internal edge never gives the normal; past it the neighbour's face (or, here,
            // this face clipped to the prism) holds whatever touches.
            if (!edgeMayTouch[k] || (flags[k] & RUBBLE_EDGE_AXIS_NONE)) continue;
            const float4 a0 = t.v[k], a1 = t.v[(k + 1u) % 3u];
            const float4 u = axes[k];
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
