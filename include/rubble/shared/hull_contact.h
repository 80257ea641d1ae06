// include/rubble/shared/hull_contact.h: the contact manifold of two flattened hulls in stage
// narrowPhase (both pipelines): SAT (shared/sat.h), then a clipped face contact or an edge
// contact, the feature choice with hysteresis, and the per-pair feature cache between steps
// (Gregorius, GDC 2015; report 3.4).
#pragma once

#include "rubble/shared/clip.h"
#include "rubble/shared/sat.h"

RUBBLE_SHARED_BEGIN

// A feature replaces the preferred one only when clearly shallower.
#define RUBBLE_RELATIVE_FACE_TOLERANCE 0.05f
#define RUBBLE_RELATIVE_EDGE_TOLERANCE 0.10f
#define RUBBLE_ABSOLUTE_TOLERANCE 0.0025f // m
// The cached feature is reused while b's pose in a's frame stays this close to the reference
// (kReuseDistance, m; kReuseRotation, per rotation-matrix entry).
#define RUBBLE_REUSE_DISTANCE 1e-3f
#define RUBBLE_REUSE_ROTATION 0.01f
// A cached edge pair's axis may turn by about 0.5 degrees (cosine) before the full test runs
// again, as much as a face normal under RUBBLE_REUSE_ROTATION; support points along it this far
// (m) below its edges' points mean the axis has left the pair's Gauss-map arcs.
#define RUBBLE_REUSE_AXIS_COSINE 0.99996f
#define RUBBLE_SUPPORT_TOLERANCE 1e-4f

// The contacts of two hulls, or the axis that separates them.
typedef struct HullContact {
    int separated;
    float separation;         // along the separating axis when separated, m
    ContactManifold contacts; // in A's frame, normal from A to B
    SatHint feature;          // the separating axis, or the feature the contacts came from
} HullContact;

// 96 bytes: what a pair keeps from one step to the next, one per pair (the device's pair order;
// SatCollision's CollisionCache::features).
typedef struct PairCache {
    RigidTransform reference; // b's pose in a's frame when the full test last ran
    SatHint feature;          // last step's separating axis or contact feature
    uint reusable;            // feature and reference come from a full test
    uint pad0, pad1, pad2;
} PairCache;
RUBBLE_STATIC_ASSERT_SIZE(PairCache, 96);

RUBBLE_FN PairCache emptyPairCacheItem(void) {
    PairCache c;
    c.reference.rotation.r0 = vec4(1.0f, 0.0f, 0.0f);
    c.reference.rotation.r1 = vec4(0.0f, 1.0f, 0.0f);
    c.reference.rotation.r2 = vec4(0.0f, 0.0f, 1.0f);
    c.reference.translation = vec4(0.0f, 0.0f, 0.0f);
    c.feature = makeSatHint(RUBBLE_SAT_NONE, 0u, 0u, 0u);
    c.reusable = 0u;
    c.pad0 = 0u;
    c.pad1 = 0u;
    c.pad2 = 0u;
    return c;
}

RUBBLE_FN int clearlyLargerItem(float x, float preferred, float relative) {
    return x > preferred + relative * fabs(preferred) + RUBBLE_ABSOLUTE_TOLERANCE;
}

// Of the faces around the deepest vertex, the one most anti-parallel to `normal`.
RUBBLE_FN uint incidentFaceItem(Hull mesh, float4 normal, uint deepest) {
    const uint first = mesh.vertexEdge[deepest];
    uint best = mesh.edges[first].face, h = first;
    float lowest = dot3(mesh.faces[best], normal);
    do {
        const uint f = mesh.edges[h].face;
        const float d = dot3(mesh.faces[f], normal);
        if (d < lowest) {
            lowest = d;
            best = f;
        }
        h = mesh.edges[mesh.edges[h].twin].next;
    } while (h != first);
    return best;
}

// A face contact in the reference hull's frame: the incident polygon clipped
// by the side planes of the reference face, the points below its plane plus the margin, reduced
// to four.
RUBBLE_FN ContactManifold clipFaceContactItem(Hull ref, FaceQuery query, Hull inc,
                                              RigidTransform incInRef, float margin, uint kind,
                                              ClipBuffers buffers) {
    const float4 rf = ref.faces[query.face];
    const float4 rfNormal = faceNormalItem(rf);
    const uint rfEdge = ref.faceEdge[query.face];
    const uint incFace =
        incidentFaceItem(inc, transformRotateInverse(incInRef, rfNormal), query.vertex);
    ClipVertex* polygon = buffers.polygon;
    ClipVertex* scratch = buffers.scratch;

    // The incident polygon in the reference frame; each vertex tagged by its half-edge.
    uint n = 0;
    const uint incFirst = inc.faceEdge[incFace];
    uint h = incFirst;
    do {
        ClipVertex v;
        v.position = transformApply(incInRef, inc.vertices[inc.edges[h].origin]);
        v.clipEdge = 0u;
        v.tag = h;
        v.segment = h;
        v.pad = 0u;
        polygon[n++] = v;
        h = inc.edges[h].next;
    } while (h != incFirst);

    // A side plane through each reference edge: perpendicular to the face, or the neighbouring
    // face where it leans in under the edge.
    h = rfEdge;
    do {
        const float4 next = ref.faces[ref.edges[ref.edges[h].twin].face];
        float4 side = faceNormalItem(next);
        float offset = next.w;
        if (dot3(next, rfNormal) >= 0.0f) {
            const float4 v0 = ref.vertices[ref.edges[h].origin];
            const float4 v1 = ref.vertices[ref.edges[ref.edges[h].next].origin];
            side = cross3(sub4(v1, v0), rfNormal);
            offset = dot3(side, v0);
        }
        n = clipPolygonItem(polygon, n, side, offset, h, scratch);
        ClipVertex* swap = polygon;
        polygon = scratch;
        scratch = swap;
        h = ref.edges[h].next;
    } while (n > 0u && h != rfEdge);

    // Below the reference plane plus the margin, midway between the surfaces.
    LocalContact* candidates = buffers.candidates;
    uint m = 0;
    for (uint i = 0; i < n; ++i) {
        const ClipVertex v = polygon[i];
        const float s = dot3(rfNormal, v.position) - rf.w;
        if (s > margin) continue;
        LocalContact c;
        c.position = sub4(v.position, scale4(rfNormal, 0.5f * s));
        c.depth = -s;
        c.feature = makeFeatureIdItem(kind, v.clipEdge, v.tag);
        c.pad0 = 0u;
        c.pad1 = 0u;
        candidates[m++] = c;
    }
    ContactManifold set = emptyContactsItem();
    set.normal = rfNormal;
    uint keep[RUBBLE_MAX_CONTACT_POINTS];
    const uint kept = reduceContactsItem(candidates, m, rfNormal, keep);
    for (uint i = 0; i < kept; ++i) {
        const LocalContact c = candidates[keep[i]];
        addContactItem(&set, c.position, c.depth, c.feature);
    }
    return set;
}

// The closest points of the two edges, with the SAT's separation along their axis.
RUBBLE_FN ContactManifold edgeContactItem(Hull a, Hull b, RigidTransform bInA, EdgeQuery q) {
    const HullEdge ea = a.edgeRecords[q.edgeA];
    const HullEdge eb = b.edgeRecords[q.edgeB];
    const float4 pb = transformApply(bInA, eb.origin);
    const SegmentPoints c =
        closestPointsOnSegmentsItem(ea.origin, add4(ea.origin, ea.direction), pb,
                                    add4(pb, transformRotate(bInA, eb.direction)));
    ContactManifold set = emptyContactsItem();
    set.normal = q.axis;
    addContactItem(&set, scale4(add4(c.c1, c.c2), 0.5f), -q.separation,
                   makeFeatureIdItem(RUBBLE_KIND_EDGES, q.edgeA, q.edgeB));
    return set;
}

// A face contact on B's face, made in B's frame and brought to A's.
RUBBLE_FN ContactManifold clipFaceContactOfBItem(Hull a, Hull b, RigidTransform bInA,
                                                 FaceQuery query, float margin,
                                                 ClipBuffers buffers) {
    ContactManifold set = clipFaceContactItem(b, query, a, transformInverse(bInA), margin,
                                              RUBBLE_KIND_FACE_B, buffers);
    for (uint i = 0; i < set.count; ++i) {
        const float4 p = transformApply(bInA, set.points[i]);
        set.points[i] = make4(p.x, p.y, p.z, set.points[i].w);
    }
    set.normal = negate4(transformRotate(bInA, set.normal));
    return set;
}

// Contacts from the face of A (ownerB = 0) or of B the SAT found (collideHulls' tryFace).
RUBBLE_FN int tryFaceItem(HullContact* r, Hull a, Hull b, RigidTransform bInA, SatResult sat,
                          float margin, int ownerB, ClipBuffers buffers) {
    if (!ownerB) {
        r->contacts =
            clipFaceContactItem(a, sat.faceA, b, bInA, margin, RUBBLE_KIND_FACE_A, buffers);
        r->feature = makeSatHint(RUBBLE_SAT_FACE_A, sat.faceA.face, 0u, sat.faceA.vertex);
        return r->contacts.count > 0u;
    }
    r->contacts = clipFaceContactOfBItem(a, b, bInA, sat.faceB, margin, buffers);
    r->feature = makeSatHint(RUBBLE_SAT_FACE_B, 0u, sat.faceB.face, sat.faceB.vertex);
    return r->contacts.count > 0u;
}

// Collides hull a with hull b, b's pose in a's frame: SAT, then faces over
// edges and last step's face owner over the other unless clearly shallower.
RUBBLE_FN HullContact collideHullsItem(Hull a, Hull b, RigidTransform bInA, float margin,
                                       SatHint hint, ClipBuffers buffers) {
    HullContact r;
    r.separated = 0;
    r.separation = 0.0f;
    r.contacts = emptyContactsItem();
    r.feature = makeSatHint(RUBBLE_SAT_NONE, 0u, 0u, 0u);
    const SatResult sat = runSatItem(a, b, bInA, margin, hint);
    if (sat.separated) {
        r.separated = 1;
        r.separation = sat.separation;
        r.feature = makeSatHint(sat.feature, sat.indexA, sat.indexB, sat.vertex);
        return r;
    }

    const float sa = sat.faceA.separation, sb = sat.faceB.separation;
    const int useB = hint.feature == RUBBLE_SAT_FACE_B
                         ? !clearlyLargerItem(sa, sb, RUBBLE_RELATIVE_FACE_TOLERANCE)
                         : clearlyLargerItem(sb, sa, RUBBLE_RELATIVE_FACE_TOLERANCE);
    const int haveEdges = sat.edges.separation > RUBBLE_LOWEST_FLOAT;
    const int useEdges = haveEdges && clearlyLargerItem(sat.edges.separation, useB ? sb : sa,
                                                        RUBBLE_RELATIVE_EDGE_TOLERANCE);
    if (!useEdges) {
        if (tryFaceItem(&r, a, b, bInA, sat, margin, useB, buffers)) return r;
        // The clipped overlap held no point: the other face, then the edges, if good enough
        // (not clearly deeper than the best axis).
        if (!clearlyLargerItem(sat.separation, useB ? sa : sb, RUBBLE_RELATIVE_EDGE_TOLERANCE) &&
            tryFaceItem(&r, a, b, bInA, sat, margin, !useB, buffers))
            return r;
        if (!haveEdges ||
            clearlyLargerItem(sat.separation, sat.edges.separation, RUBBLE_RELATIVE_EDGE_TOLERANCE)) {
            r.contacts = emptyContactsItem();
            return r;
        }
    }
    r.contacts = edgeContactItem(a, b, bInA, sat.edges);
    r.feature = makeSatHint(RUBBLE_SAT_EDGES, sat.edges.edgeA, sat.edges.edgeB, 0u);
    return r;
}

// Contacts from a known feature, skipping the search; without a
// usable feature, the full test.
RUBBLE_FN HullContact collideHullsFromFeatureItem(Hull a, Hull b, RigidTransform bInA,
                                                  SatHint feature, float margin,
                                                  ClipBuffers buffers) {
    HullContact r;
    r.separated = 0;
    r.separation = 0.0f;
    r.contacts = emptyContactsItem();
    r.feature = feature;
    if (feature.feature == RUBBLE_SAT_FACE_A && feature.indexA < a.faceCount) {
        const FaceQuery q = queryFaceItem(a, feature.indexA, b, bInA, feature.vertex);
        r.feature.vertex = q.vertex;
        r.separated = q.separation > margin;
        r.separation = q.separation;
        if (!r.separated)
            r.contacts = clipFaceContactItem(a, q, b, bInA, margin, RUBBLE_KIND_FACE_A, buffers);
        return r;
    }
    if (feature.feature == RUBBLE_SAT_FACE_B && feature.indexB < b.faceCount) {
        const FaceQuery q =
            queryFaceItem(b, feature.indexB, a, transformInverse(bInA), feature.vertex);
        r.feature.vertex = q.vertex;
        r.separated = q.separation > margin;
        r.separation = q.separation;
        if (!r.separated) r.contacts = clipFaceContactOfBItem(a, b, bInA, q, margin, buffers);
        return r;
    }
    if (feature.feature == RUBBLE_SAT_EDGES && feature.indexA < a.edgeCount &&
        feature.indexB < b.edgeCount) {
        const HullEdge ea = a.edgeRecords[feature.indexA];
        const float4 dirB = transformRotate(bInA, b.edgeRecords[feature.indexB].direction);
        const EdgeAxis axis = edgeAxisItem(ea.origin, ea.direction, dirB, a.centroid);
        if (axis.valid) {
            EdgeQuery q;
            q.separation = separationAlongItem(a, b, bInA, axis.axis);
            q.edgeA = feature.indexA;
            q.edgeB = feature.indexB;
            q.axis = axis.axis;
            r.separated = q.separation > margin;
            r.separation = q.separation;
            if (!r.separated) r.contacts = edgeContactItem(a, b, bInA, q);
            return r;
        }
    }
    return collideHullsItem(a, b, bInA, margin, feature, buffers);
}

// b's pose in a's frame within the reuse limits of the cache's reference.
RUBBLE_FN int poseCloseItem(RigidTransform bInA, RigidTransform reference) {
    const float4 dt = sub4(bInA.translation, reference.translation);
    if (!(sqrt(dot3(dt, dt)) <= RUBBLE_REUSE_DISTANCE)) return 0;
    const Mat3 r = bInA.rotation, q = reference.rotation;
    // Column by column, as glm compares them.
    const float c0 = max3Item(fabs(r.r0.x - q.r0.x), fabs(r.r1.x - q.r1.x), fabs(r.r2.x - q.r2.x));
    if (!(c0 <= RUBBLE_REUSE_ROTATION)) return 0;
    const float c1 = max3Item(fabs(r.r0.y - q.r0.y), fabs(r.r1.y - q.r1.y), fabs(r.r2.y - q.r2.y));
    if (!(c1 <= RUBBLE_REUSE_ROTATION)) return 0;
    const float c2 = max3Item(fabs(r.r0.z - q.r0.z), fabs(r.r1.z - q.r1.z), fabs(r.r2.z - q.r2.z));
    return c2 <= RUBBLE_REUSE_ROTATION;
}

// The axis of an edge pair (undirected edge indices of a and b) at b's pose in a's frame:
// the unit cross product of the two edges turned out of a; not valid when the
// edges are closer to parallel than RUBBLE_PARALLEL_SINE.
RUBBLE_FN EdgeAxis edgePairAxisItem(Hull a, uint edgeA, Hull b, uint edgeB, RigidTransform bInA) {
    const HullEdge ea = a.edgeRecords[edgeA];
    return edgeAxisItem(ea.origin, ea.direction,
                        transformRotate(bInA, b.edgeRecords[edgeB].direction), a.centroid);
}

// True while a cached edge pair's axis at this pose is within RUBBLE_REUSE_AXIS_COSINE of its
// axis at the reference, and the pair still spans a face of the Minkowski difference: along its
// axis the edges' own points are the support points.
RUBBLE_FN int edgeAxisHoldsItem(Hull a, Hull b, RigidTransform bInA, RigidTransform reference,
                                SatHint edges) {
    const EdgeAxis now = edgePairAxisItem(a, edges.indexA, b, edges.indexB, bInA);
    const EdgeAxis then = edgePairAxisItem(a, edges.indexA, b, edges.indexB, reference);
    if (!now.valid || !then.valid || dot3(now.axis, then.axis) < RUBBLE_REUSE_AXIS_COSINE)
        return 0;
    const float byEdges = dot3(now.axis, sub4(transformApply(bInA, b.edgeRecords[edges.indexB].origin),
                                              a.edgeRecords[edges.indexA].origin));
    return separationAlongItem(a, b, bInA, now.axis) >= byEdges - RUBBLE_SUPPORT_TOLERANCE;
}

// Collides with the pair's cache: the feature is reused while the pose
// stays close to the reference (and a cached edge pair's axis holds: edgeAxisHoldsItem), else
// the full test runs and becomes the new reference.
RUBBLE_FN HullContact collideHullsCachedItem(Hull a, Hull b, RigidTransform bInA, PairCache* cache,
                                             float margin, ClipBuffers buffers) {
    int close = cache->reusable && cache->feature.feature != RUBBLE_SAT_NONE &&
                poseCloseItem(bInA, cache->reference);
    // The axis of two nearly parallel edges swings with the slightest turn (by the turn over
    // the sine of their angle): it is the same axis only while it points the same way and the
    // edges are still the support features along it.
    if (close && cache->feature.feature == RUBBLE_SAT_EDGES)
        close = edgeAxisHoldsItem(a, b, bInA, cache->reference, cache->feature);
    if (close) {
        const HullContact r =
            collideHullsFromFeatureItem(a, b, bInA, cache->feature, margin, buffers);
        if (r.separated || r.contacts.count > 0u) {
            cache->feature.vertex = r.feature.vertex;
            return r;
        }
    }
    const HullContact r = collideHullsItem(a, b, bInA, margin, cache->feature, buffers);
    cache->feature = r.feature;
    cache->reference = bInA;
    cache->reusable = 1u;
    return r;
}

RUBBLE_SHARED_END
