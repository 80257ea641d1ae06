// include/rubble/shared/sat.h: the separating axis test between two flattened hulls, part of
// stage narrowPhase on both pipelines (SatCollision on the CPU, kernels/sat.cl on the device):
// face queries, the edge query with Gauss-map pruning, runSatItem (Gregorius, GDC 2013; physics
// report 3.3).
#pragma once

#include "rubble/shared/hull.h"

RUBBLE_SHARED_BEGIN

// Which feature pair defines an axis.
#define RUBBLE_SAT_NONE 0u
#define RUBBLE_SAT_FACE_A 1u
#define RUBBLE_SAT_FACE_B 2u
#define RUBBLE_SAT_EDGES 3u

// Edge pairs closer to parallel than this sine give no axis.
#define RUBBLE_PARALLEL_SINE 1e-3f
// The lowest float: a query that has not run.
#define RUBBLE_LOWEST_FLOAT (-3.40282347e+38f)

// The best face of one hull.
typedef struct FaceQuery {
    float separation; // m; > 0: a gap
    uint face;        // face of the hull whose faces were tried
    uint vertex;      // the other hull's support vertex for that face
} FaceQuery;

// The best edge pair.
typedef struct EdgeQuery {
    float separation;   // m; > 0: a gap
    uint edgeA, edgeB;  // undirected edge indices
    float4 axis;        // unit, A's frame, from A to B
} EdgeQuery;

// 16 bytes: a feature to test first, kept from last step.
typedef struct SatHint {
    uint feature;        // RUBBLE_SAT_*
    uint indexA, indexB; // face of A or B, or edges of A and B
    uint vertex;         // faces: the other hull's support vertex, where climbs start
} SatHint;
RUBBLE_STATIC_ASSERT_SIZE(SatHint, 16);

// The outcome of one separating axis test.
typedef struct SatResult {
    int separated;
    uint feature;
    float separation;
    uint indexA, indexB, vertex;
    float4 axis;
    FaceQuery faceA, faceB;
    EdgeQuery edges;
} SatResult;

// An edge pair's axis, when the edges are not parallel.
typedef struct EdgeAxis {
    float4 axis;
    int valid;
} EdgeAxis;

RUBBLE_FN FaceQuery noFaceQuery(void) {
    FaceQuery q;
    q.separation = RUBBLE_LOWEST_FLOAT;
    q.face = 0u;
    q.vertex = 0u;
    return q;
}

RUBBLE_FN EdgeQuery noEdgeQuery(void) {
    EdgeQuery q;
    q.separation = RUBBLE_LOWEST_FLOAT;
    q.edgeA = 0u;
    q.edgeB = 0u;
    q.axis = vec4(0.0f, 0.0f, 0.0f);
    return q;
}

RUBBLE_FN SatHint makeSatHint(uint feature, uint indexA, uint indexB, uint vertex) {
    SatHint h;
    h.feature = feature;
    h.indexA = indexA;
    h.indexB = indexB;
    h.vertex = vertex;
    return h;
}

RUBBLE_FN float4 faceNormalItem(float4 plane) { return vec4(plane.x, plane.y, plane.z); }

// The unit axis eA x eB turned out of A.
RUBBLE_FN EdgeAxis edgeAxisItem(float4 pointA, float4 dirA, float4 dirB, float4 centroidA) {
    EdgeAxis r;
    r.valid = 0;
    r.axis = vec4(0.0f, 0.0f, 0.0f);
    const float4 n = cross3(dirA, dirB);
    const float n2 = dot3(n, n);
    const float limit = RUBBLE_PARALLEL_SINE * RUBBLE_PARALLEL_SINE * dot3(dirA, dirA) * dot3(dirB, dirB);
    if (!(n2 > limit)) return r;
    const float4 axis = scale4(n, 1.0f / sqrt(n2));
    r.axis = dot3(axis, sub4(pointA, centroidA)) < 0.0f ? negate4(axis) : axis;
    r.valid = 1;
    return r;
}

// Support-point separation along an axis, climbs from vertex 0 of each.
RUBBLE_FN float separationAlongItem(Hull a, Hull b, RigidTransform bInA, float4 axis) {
    const uint startA = supportVertexItem(a, axis, 0u);
    const uint startB = supportVertexItem(b, transformRotateInverse(bInA, negate4(axis)), 0u);
    return dot3(axis, transformApply(bInA, b.vertices[startB])) - dot3(axis, a.vertices[startA]);
}

// Face query of one face of a.
RUBBLE_FN FaceQuery queryFaceItem(Hull a, uint face, Hull b, RigidTransform bInA, uint startVertex) {
    const float4 f = a.faces[face];
    const float4 normal = faceNormalItem(f);
    const uint v = supportVertexItem(b, transformRotateInverse(bInA, negate4(normal)),
                                     startVertex < b.vertexCount ? startVertex : 0u);
    FaceQuery q;
    q.separation = dot3(normal, transformApply(bInA, b.vertices[v])) - f.w;
    q.face = face;
    q.vertex = v;
    return q;
}

// Face query over every face of a, stopping above `stopAbove`.
RUBBLE_FN FaceQuery queryFaceDirectionsItem(Hull a, Hull b, RigidTransform bInA, float stopAbove) {
    FaceQuery best = noFaceQuery();
    uint start = 0u;
    for (uint f = 0; f < a.faceCount; ++f) {
        const float4 face = a.faces[f];
        const float4 normal = faceNormalItem(face);
        start = supportVertexItem(b, transformRotateInverse(bInA, negate4(normal)), start);
        const float s = dot3(normal, transformApply(bInA, b.vertices[start])) - face.w;
        if (s > best.separation) {
            best.separation = s;
            best.face = f;
            best.vertex = start;
            if (s > stopAbove) break;
        }
    }
    return best;
}

// Edge query over the pairs whose Gauss-map arcs cross: for each edge of
// b, the arc test against every edge of a, in a's order.
RUBBLE_FN EdgeQuery queryEdgeDirectionsItem(Hull a, Hull b, RigidTransform bInA, float stopAbove) {
    EdgeQuery best = noEdgeQuery();
    for (uint kb = 0; kb < b.edgeCount; ++kb) {
        const HullEdge eb = b.edgeRecords[kb];
        const float4 c = negate4(transformRotate(bInA, eb.normalLeft));
        const float4 d = negate4(transformRotate(bInA, eb.normalRight));
        const float4 dxc = transformRotate(bInA, eb.arc);
        int placed = 0;
        float4 pointB = vec4(0.0f, 0.0f, 0.0f), dirB = vec4(0.0f, 0.0f, 0.0f);
        for (uint ka = 0; ka < a.edgeCount; ++ka) {
            const RUBBLE_GLOBAL HullEdge* ea = a.edgeRecords + ka;
            const float4 arc = ea->arc;
            const float cba = dot3(c, arc);
            const float dba = dot3(d, arc);
            const float adc = dot3(ea->normalLeft, dxc);
            const float bdc = dot3(ea->normalRight, dxc);
            if (!((cba * dba < 0.0f) & (adc * bdc < 0.0f) & (cba * bdc > 0.0f))) continue;
            if (!placed) {
                pointB = transformApply(bInA, eb.origin);
                dirB = transformRotate(bInA, eb.direction);
                placed = 1;
            }
            const float4 originA = ea->origin;
            const EdgeAxis axis = edgeAxisItem(originA, ea->direction, dirB, a.centroid);
            if (!axis.valid) continue;
            const float s = dot3(axis.axis, sub4(pointB, originA));
            if (s > best.separation) {
                best.separation = s;
                best.edgeA = ka;
                best.edgeB = kb;
                best.axis = axis.axis;
                if (s > stopAbove) return best;
            }
        }
    }
    return best;
}

RUBBLE_FN void settleSatItem(SatResult* r, uint feature, float s, uint ia, uint ib, float4 axis,
                             uint vertex) {
    r->feature = feature;
    r->separation = s;
    r->indexA = ia;
    r->indexB = ib;
    r->axis = axis;
    r->vertex = vertex;
}

// The separating axis test (runSat, with the pruned edge query): the hint's axis first, then
// the faces of a, the faces of b and the edges, each stopping above `margin`; without a
// separating axis the largest separation wins, faces before edges on ties.
RUBBLE_FN SatResult runSatItem(Hull a, Hull b, RigidTransform bInA, float margin, SatHint hint) {
    SatResult r;
    r.separated = 0;
    r.feature = RUBBLE_SAT_NONE;
    r.separation = 0.0f;
    r.indexA = 0u;
    r.indexB = 0u;
    r.vertex = 0u;
    r.axis = vec4(0.0f, 0.0f, 0.0f);
    r.faceA = noFaceQuery();
    r.faceB = noFaceQuery();
    r.edges = noEdgeQuery();
    const RigidTransform aInB = transformInverse(bInA);

    // Last step's axis first.
    if (hint.feature == RUBBLE_SAT_FACE_A && hint.indexA < a.faceCount) {
        const FaceQuery q = queryFaceItem(a, hint.indexA, b, bInA, hint.vertex);
        settleSatItem(&r, RUBBLE_SAT_FACE_A, q.separation, hint.indexA, 0u,
                      faceNormalItem(a.faces[hint.indexA]), q.vertex);
    } else if (hint.feature == RUBBLE_SAT_FACE_B && hint.indexB < b.faceCount) {
        const FaceQuery q = queryFaceItem(b, hint.indexB, a, aInB, hint.vertex);
        settleSatItem(&r, RUBBLE_SAT_FACE_B, q.separation, 0u, hint.indexB,
                      negate4(transformRotate(bInA, faceNormalItem(b.faces[hint.indexB]))),
                      q.vertex);
    } else if (hint.feature == RUBBLE_SAT_EDGES && hint.indexA < a.edgeCount &&
               hint.indexB < b.edgeCount) {
        const HullEdge ea = a.edgeRecords[hint.indexA];
        const float4 dirB = transformRotate(bInA, b.edgeRecords[hint.indexB].direction);
        const EdgeAxis axis = edgeAxisItem(ea.origin, ea.direction, dirB, a.centroid);
        if (axis.valid)
            settleSatItem(&r, RUBBLE_SAT_EDGES, separationAlongItem(a, b, bInA, axis.axis),
                          hint.indexA, hint.indexB, axis.axis, 0u);
    }
    if (r.feature != RUBBLE_SAT_NONE && r.separation > margin) {
        r.separated = 1;
        return r;
    }
    r.feature = RUBBLE_SAT_NONE;

    r.faceA = queryFaceDirectionsItem(a, b, bInA, margin);
    settleSatItem(&r, RUBBLE_SAT_FACE_A, r.faceA.separation, r.faceA.face, 0u,
                  faceNormalItem(a.faces[r.faceA.face]), r.faceA.vertex);
    if (r.separation > margin) {
        r.separated = 1;
        return r;
    }
    r.faceB = queryFaceDirectionsItem(b, a, aInB, margin);
    if (r.faceB.separation > r.separation)
        settleSatItem(&r, RUBBLE_SAT_FACE_B, r.faceB.separation, 0u, r.faceB.face,
                      negate4(transformRotate(bInA, faceNormalItem(b.faces[r.faceB.face]))),
                      r.faceB.vertex);
    if (r.separation > margin) {
        r.separated = 1;
        return r;
    }
    r.edges = queryEdgeDirectionsItem(a, b, bInA, margin);
    if (r.edges.separation > r.separation)
        settleSatItem(&r, RUBBLE_SAT_EDGES, r.edges.separation, r.edges.edgeA, r.edges.edgeB,
                      r.edges.axis, 0u);
    r.separated = r.separation > margin;
    return r;
}

RUBBLE_SHARED_END
