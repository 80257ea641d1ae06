// include/rubble/shared/hull.h: the shapes of a world flattened for the SAT narrow phase
// (host/collision/hull_data.cpp fills them once per world from host/geometry/half_edge.h's meshes):
// the per-shape record, half-edges, faces, edge records, vertex rings; rigid transforms as
// host/collision/transform.h has them; support points by hill climbing.
// Compiled by the host and by kernels/sat.cl; the arithmetic follows glm's operand order, so
// that both give the same bits.
#pragma once

#include "rubble/shared/body.h"

RUBBLE_SHARED_BEGIN

// What a shape collides as (HullShape.kind).
#define RUBBLE_SHAPE_HULL 0u   // box, convex and mesh: their half-edge hull
#define RUBBLE_SHAPE_SPHERE 1u // centre and radius
#define RUBBLE_SHAPE_PLANE 2u  // infinite, static: solid below dot(normal, x) = offset
#define RUBBLE_SHAPE_CAPSULE 3u // radius and half height (capsule_contact.h), and bounds around
                                // the segment from -y to +y swept by it

// A hull face has at most this many vertices on the device: clipping buffers live in private
// memory (an incident face, plus one vertex per reference edge, plus one), and their size is
// what the narrow phase's speed depends on most, so they are no larger than the hulls need. Boxes
// have 4, the shipped meshes' hulls 8 at most; a hull with a larger face is refused when the
// pipeline is made (host/gpu/hull_data.cpp).
#define RUBBLE_HULL_MAX_FACE_VERTICES 16u
#define RUBBLE_CLIP_CAPACITY (2u * RUBBLE_HULL_MAX_FACE_VERTICES + 1u)

// 112 bytes, one per shape of the world. Indices in the hull arrays of a shape are its own
// (0 .. count - 1, as in its HalfEdgeMesh); the starts place them in the concatenated arrays.
typedef struct HullShape {
    float4 boundsMin;     // hull: axis-aligned bounds of the vertices, shape frame, m (w = 0)
    float4 boundsMax;     // hull, m (w = 0)
    float4 centroid;      // hull: mean of the vertices, m (w = 0)
    float4 plane;         // plane: unit normal out of the solid (xyz), offset (w, m)
    uint kind;            // RUBBLE_SHAPE_*
    float radius;         // sphere, m
    float boundingRadius; // largest distance of the shape from its origin, m
    uint vertexStart;     // first vertex (vertices, vertexEdges, neighbourStart)
    uint vertexCount;
    uint halfEdgeStart;   // first half-edge (halfEdges); twins at 2k and 2k + 1
    uint edgeStart;       // first undirected edge record (edges)
    uint edgeCount;
    uint faceStart;       // first face (faces, faceEdges)
    uint faceCount;
    float halfHeight;     // capsule: half the length of its segment along local y, m
    uint pad1;
} HullShape;
RUBBLE_STATIC_ASSERT_SIZE(HullShape, 112);

// 16 bytes: one directed edge, as host/geometry/half_edge.h's HalfEdge.
typedef struct HullHalfEdge {
    uint origin; // the vertex it leaves
    uint face;   // the face on its left, seen from outside
    uint next;   // the next half-edge counter-clockwise around that face
    uint twin;   // the same edge walked the other way
} HullHalfEdge;
RUBBLE_STATIC_ASSERT_SIZE(HullHalfEdge, 16);

// 80 bytes: one undirected edge k (half-edge 2k) as the edge query reads it (HalfEdgeEdge).
typedef struct HullEdge {
    float4 origin;      // vertex of half-edge 2k, m
    float4 direction;   // to the other vertex, m (not normalised)
    float4 normalLeft;  // face of half-edge 2k, unit
    float4 normalRight; // face of half-edge 2k + 1, unit
    float4 arc;         // cross(normalRight, normalLeft): the edge's arc on the Gauss map
} HullEdge;
RUBBLE_STATIC_ASSERT_SIZE(HullEdge, 80);

// The concatenated arrays of every shape (device buffers; host vectors in tests).
typedef struct HullArrays {
    RUBBLE_GLOBAL const float4* vertices;       // m (w = 0)
    RUBBLE_GLOBAL const uint* vertexEdges;      // a half-edge leaving each vertex
    RUBBLE_GLOBAL const uint* neighbourStart;   // per vertex and one more: into neighbours
    RUBBLE_GLOBAL const uint* neighbours;       // vertex rings (the shape's own indices)
    RUBBLE_GLOBAL const HullHalfEdge* halfEdges;
    RUBBLE_GLOBAL const float4* faces;          // unit normal (xyz) and offset (w, m)
    RUBBLE_GLOBAL const uint* faceEdges;        // a half-edge of each face
    RUBBLE_GLOBAL const HullEdge* edges;
} HullArrays;

// One hull: the arrays moved to its first elements, so that it is indexed as its HalfEdgeMesh.
// Lives in private memory only (it holds pointers).
typedef struct Hull {
    RUBBLE_GLOBAL const float4* vertices;
    RUBBLE_GLOBAL const uint* vertexEdge;
    RUBBLE_GLOBAL const uint* neighbourStart; // absolute offsets into neighbours
    RUBBLE_GLOBAL const uint* neighbours;
    RUBBLE_GLOBAL const HullHalfEdge* edges;
    RUBBLE_GLOBAL const float4* faces;
    RUBBLE_GLOBAL const uint* faceEdge;
    RUBBLE_GLOBAL const HullEdge* edgeRecords;
    uint vertexCount, edgeCount, faceCount;
    float4 centroid;
} Hull;

RUBBLE_FN Hull hullOfItem(HullArrays a, HullShape s) {
    Hull h;
    h.vertices = a.vertices + s.vertexStart;
    h.vertexEdge = a.vertexEdges + s.vertexStart;
    h.neighbourStart = a.neighbourStart + s.vertexStart;
    h.neighbours = a.neighbours;
    h.edges = a.halfEdges + s.halfEdgeStart;
    h.faces = a.faces + s.faceStart;
    h.faceEdge = a.faceEdges + s.faceStart;
    h.edgeRecords = a.edges + s.edgeStart;
    h.vertexCount = s.vertexCount;
    h.edgeCount = s.edgeCount;
    h.faceCount = s.faceCount;
    h.centroid = s.centroid;
    return h;
}

// 64 bytes: x' = rotation x + translation (host/collision/transform.h's Transform).
typedef struct RigidTransform {
    Mat3 rotation;
    float4 translation; // m (w = 0)
} RigidTransform;
RUBBLE_STATIC_ASSERT_SIZE(RigidTransform, 64);

// glm's operator order: R v row by row; v R (= R^T v) column by column.
RUBBLE_FN float4 transformRotate(RigidTransform t, float4 v) { return mat3MulVec(t.rotation, v); }
RUBBLE_FN float4 transformRotateInverse(RigidTransform t, float4 v) {
    const Mat3 r = t.rotation;
    return vec4(r.r0.x * v.x + r.r1.x * v.y + r.r2.x * v.z, r.r0.y * v.x + r.r1.y * v.y + r.r2.y * v.z,
                r.r0.z * v.x + r.r1.z * v.y + r.r2.z * v.z);
}
RUBBLE_FN float4 transformApply(RigidTransform t, float4 p) {
    return add4(transformRotate(t, p), t.translation);
}
RUBBLE_FN float4 transformApplyInverse(RigidTransform t, float4 p) {
    return transformRotateInverse(t, sub4(p, t.translation));
}
// The body-to-world transform of a pose (transformOf).
RUBBLE_FN RigidTransform transformOfPose(BodyPose pose) {
    RigidTransform t;
    t.rotation = mat3FromQuat(pose.orientation);
    t.translation = vec4(pose.position.x, pose.position.y, pose.position.z);
    return t;
}
RUBBLE_FN RigidTransform transformInverse(RigidTransform t) {
    RigidTransform r;
    r.rotation = mat3Transpose(t.rotation);
    r.translation = scale4(mat3MulVec(r.rotation, t.translation), -1.0f);
    return r;
}
// b's frame seen from a's frame (relative).
RUBBLE_FN RigidTransform transformRelative(RigidTransform a, RigidTransform b) {
    const Mat3 rt = mat3Transpose(a.rotation);
    RigidTransform r;
    r.rotation = mat3Mul(rt, b.rotation);
    r.translation = mat3MulVec(rt, sub4(b.translation, a.translation));
    return r;
}

RUBBLE_FN float4 negate4(float4 v) { return vec4(-v.x, -v.y, -v.z); }
RUBBLE_FN float4 abs4(float4 v) { return vec4(fabs(v.x), fabs(v.y), fabs(v.z)); }
// std::clamp's order of tests.
RUBBLE_FN float clampItem(float x, float lo, float hi) { return x < lo ? lo : (hi < x ? hi : x); }
// A unit vector as glm::normalize makes it: v times 1 / sqrt(v . v).
RUBBLE_FN float4 glmNormalize(float4 v) { return scale4(v, 1.0f / sqrt(dot3(v, v))); }
// v / s component by component (glm's vector by scalar division).
RUBBLE_FN float4 divide4(float4 v, float s) { return vec4(v.x / s, v.y / s, v.z / s); }

// The vertex furthest along d by hill climbing from `start` (supportVertex): moves to the
// neighbour that improves most until none does.
RUBBLE_FN uint supportVertexItem(Hull m, float4 d, uint start) {
    uint best = start;
    float bestDot = dot3(d, m.vertices[best]);
    for (;;) {
        uint climb = best;
        float climbDot = bestDot;
        const uint end = m.neighbourStart[best + 1u];
        for (uint i = m.neighbourStart[best]; i < end; ++i) {
            const uint v = m.neighbours[i];
            const float d2 = dot3(d, m.vertices[v]);
            if (d2 > climbDot) {
                climbDot = d2;
                climb = v;
            }
        }
        if (climb == best) return best;
        best = climb;
        bestDot = climbDot;
    }
}

RUBBLE_SHARED_END
