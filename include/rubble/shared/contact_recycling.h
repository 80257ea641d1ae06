// include/rubble/shared/contact_recycling.h: contact recycling in stage narrowPhase (both
// pipelines): a hull pair keeps its last manifold in the frames of its two bodies and, while the
// bodies have moved little against each other since it was made, rebuilds it under the current
// transforms instead of running SAT and clipping (Box2D v3.2's contact recycling); a separated
// pair stays separated while the bodies have moved against each other by less than its gap.
#pragma once

#include "rubble/shared/narrow_phase.h"

RUBBLE_SHARED_BEGIN

// A manifold is recycled while no point of either body can have moved by more than this against
// the other since it was made (m), while the pair's margin is widened by no more than this for
// the bodies' motion in the step, and for at most RUBBLE_RECYCLE_MAX_AGE steps in a row. A point
// that was beyond the 4 mm contact margin when the manifold was made stays at least 3.5 mm clear
// through the step, so no contact is missed; with 1 mm and 8 steps the crates of a collapsing
// pile sink 1-3 mm deeper (docs/collision.md, "Contact recycling").
#define RUBBLE_RECYCLE_DISTANCE 2.5e-4f
#define RUBBLE_RECYCLE_MAX_AGE 4u

// 240 bytes: a hull pair's manifold in the frames of its bodies, one per pair beside its
// PairCache (SatCollision's CollisionCache::features).
typedef struct RecycledManifold {
    RigidTransform made; // b's pose in a's frame when the manifold was made
    float4 normal;       // unit, from a to b: in a's frame, or in b's when normalInB
    float4 pointA[4];    // on a's surface, a's frame, m
    float4 pointB[4];    // on b's surface, b's frame, m
    uint features[4];    // the manifold's feature ids, kept for warm starting
    uint count;          // points, 0 to 4; 0: nothing to recycle
    uint normalInB;      // 1 when the reference face is b's (feature kind RUBBLE_KIND_FACE_B)
    uint age;            // steps recycled since the manifold was made
    float gap;           // separated (count 0): the separation along the separating axis, m
} RecycledManifold;
RUBBLE_STATIC_ASSERT_SIZE(RecycledManifold, 240);

RUBBLE_FN RecycledManifold emptyRecycledManifoldItem(void) {
    RecycledManifold r;
    r.made.rotation.r0 = vec4(1.0f, 0.0f, 0.0f);
    r.made.rotation.r1 = vec4(0.0f, 1.0f, 0.0f);
    r.made.rotation.r2 = vec4(0.0f, 0.0f, 1.0f);
    r.made.translation = vec4(0.0f, 0.0f, 0.0f);
    r.normal = vec4(0.0f, 1.0f, 0.0f);
    for (uint i = 0; i < RUBBLE_MAX_CONTACT_POINTS; ++i) {
        r.pointA[i] = make4(0.0f, 0.0f, 0.0f, 0.0f);
        r.pointB[i] = make4(0.0f, 0.0f, 0.0f, 0.0f);
        r.features[i] = 0u;
    }
    r.count = 0u;
    r.normalInB = 0u;
    r.age = 0u;
    r.gap = 0.0f;
    return r;
}

// A hull pair's manifold in a's frame (normal from a to b) at b's pose bInA, kept in the bodies'
// frames: each point's two surface points, at depth / 2 on either side of it along the normal;
// or, for a separated pair, its separation.
RUBBLE_FN RecycledManifold recycleManifoldItem(HullContact hc, RigidTransform bInA) {
    const ContactManifold inA = hc.contacts;
    RecycledManifold r = emptyRecycledManifoldItem();
    r.made = bInA;
    r.gap = hc.separated ? hc.separation : 0.0f;
    r.count = inA.count;
    r.normalInB = inA.count > 0u && (inA.features[0] >> 30) == RUBBLE_KIND_FACE_B;
    r.normal = r.normalInB ? transformRotateInverse(bInA, inA.normal) : inA.normal;
    for (uint i = 0; i < inA.count; ++i) {
        const float4 p = vec4(inA.points[i].x, inA.points[i].y, inA.points[i].z);
        const float4 half = scale4(inA.normal, 0.5f * inA.points[i].w);
        r.pointA[i] = add4(p, half);
        r.pointB[i] = transformApplyInverse(bInA, sub4(p, half));
        r.features[i] = inA.features[i];
    }
    return r;
}

// The farthest a point of either body can have moved against the other since `made`, m: the
// smaller of the bound in a's frame (b's origin moved, plus the turn's chord times b's radius)
// and the bound in b's frame. ||R - R0||_F / sqrt(2) is the chord 2 sin(theta / 2) of the turn.
RUBBLE_FN float recycleDriftItem(RigidTransform made, RigidTransform bInA, float radiusA,
                                 float radiusB) {
    const Mat3 r = bInA.rotation, q = made.rotation;
    const float4 d0 = sub4(r.r0, q.r0), d1 = sub4(r.r1, q.r1), d2 = sub4(r.r2, q.r2);
    const float chord = sqrt(0.5f * (dot3(d0, d0) + dot3(d1, d1) + dot3(d2, d2)));
    const float inA = length3(sub4(bInA.translation, made.translation)) + chord * radiusB;
    const float inB = length3(sub4(transformRotateInverse(bInA, bInA.translation),
                                   transformRotateInverse(made, made.translation))) +
                      chord * radiusA;
    return fmin(inA, inB);
}

// Whether the pair's kept manifold may stand for a new one this step. A separated pair stays
// separated by more than the margin while the drift is below its gap less the margin: no point
// of b came closer to a along the separating axis by more than the drift.
RUBBLE_FN int recyclableItem(RecycledManifold r, RigidTransform bInA, float radiusA, float radiusB,
                             float margin) {
    if (r.count == 0u)
        return r.gap > margin && recycleDriftItem(r.made, bInA, radiusA, radiusB) < r.gap - margin;
    return r.age < RUBBLE_RECYCLE_MAX_AGE &&
           margin <= RUBBLE_CONTACT_MARGIN + RUBBLE_RECYCLE_DISTANCE &&
           recycleDriftItem(r.made, bInA, radiusA, radiusB) <= RUBBLE_RECYCLE_DISTANCE;
}

// The kept manifold at b's pose bInA, in a's frame: the same surface points and feature ids,
// each point's separation along the normal (turned with its reference body) recomputed, placed
// midway as clipping places it (from b's point for a face of a, from a's for a face of b, between
// the two for edges); points that separate by more than the margin are left out.
RUBBLE_FN ContactManifold rebuildRecycledItem(RecycledManifold r, RigidTransform bInA,
                                              float margin) {
    ContactManifold m = emptyContactsItem();
    const float4 n = r.normalInB ? transformRotate(bInA, r.normal) : r.normal;
    m.normal = n;
    for (uint i = 0; i < r.count; ++i) {
        const float4 pa = r.pointA[i];
        const float4 pb = transformApply(bInA, r.pointB[i]);
        const float s = dot3(n, sub4(pb, pa));
        if (s > margin) continue;
        const uint kind = r.features[i] >> 30;
        const float4 position = kind == RUBBLE_KIND_FACE_A   ? sub4(pb, scale4(n, 0.5f * s))
                                : kind == RUBBLE_KIND_FACE_B ? add4(pa, scale4(n, 0.5f * s))
                                                             : scale4(add4(pa, pb), 0.5f);
        addContactItem(&m, position, -s, r.features[i]);
    }
    return m;
}

// collideShapesClippingInItem with recycling: a hull pair whose kept manifold is recyclable gets
// it rebuilt (when a point is still within the margin) or no contact (when it was separated);
// otherwise the pair is collided with its cache and its manifold kept for the next steps. Other
// pairs (spheres, planes, capsules) are collided as without recycling and leave `recycled` alone.
RUBBLE_FN ContactManifold collideShapesRecyclingInItem(HullArrays arrays, HullShape a,
                                                       RigidTransform ta, HullShape b,
                                                       RigidTransform tb, PairCache* cache,
                                                       RecycledManifold* recycled, float margin,
                                                       ClipBuffers buffers) {
    if (a.kind != RUBBLE_SHAPE_HULL || b.kind != RUBBLE_SHAPE_HULL)
        return collideShapesClippingInItem(arrays, a, ta, b, tb, cache, margin, buffers);
    const RigidTransform bInA = transformRelative(ta, tb);
    if (recyclableItem(*recycled, bInA, a.boundingRadius, b.boundingRadius, margin)) {
        if (recycled->count == 0u) return emptyContactsItem();
        const ContactManifold m = rebuildRecycledItem(*recycled, bInA, margin);
        if (m.count > 0u) {
            recycled->age += 1u;
            return contactsToWorldItem(m, ta, 0);
        }
    }
    const HullContact hc = collideHullsCachedItem(hullOfItem(arrays, a), hullOfItem(arrays, b),
                                                  bInA, cache, margin, buffers);
    *recycled = recycleManifoldItem(hc, bInA);
    return contactsToWorldItem(hc.contacts, ta, 0);
}

RUBBLE_SHARED_END
