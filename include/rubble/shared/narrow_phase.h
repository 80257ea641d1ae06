// include/rubble/shared/narrow_phase.h: stage narrowPhase for one pair, both pipelines: dispatch
// by shape kind to the hull (SAT and clipping), sphere and plane contacts, results brought to the
// world frame. SatCollision::narrowPhase and kernels/sat.cl run it once per pair.
#pragma once

#include "rubble/shared/capsule_contact.h"
#include "rubble/shared/hull_contact.h"
#include "rubble/shared/primitive_contact.h"

RUBBLE_SHARED_BEGIN

// A contact set from a shape's frame to the world; flip turns the normal around.
RUBBLE_FN ContactManifold contactsToWorldItem(ContactManifold inShape, RigidTransform t, int flip) {
    ContactManifold w = inShape;
    for (uint i = 0; i < w.count; ++i) {
        const float4 p = transformApply(t, inShape.points[i]);
        w.points[i] = make4(p.x, p.y, p.z, inShape.points[i].w);
    }
    w.normal = transformRotate(t, inShape.normal);
    if (flip) w.normal = negate4(w.normal);
    return w;
}

// A plane shape at a body's transform: n' = R n, d' = d + n' . t; xyz normal, w
// offset.
RUBBLE_FN float4 worldPlaneItem(HullShape s, RigidTransform t) {
    const float4 n = transformRotate(t, faceNormalItem(s.plane));
    return make4(n.x, n.y, n.z, s.plane.w + dot3(n, t.translation));
}

// A plane against any other shape; the normal points from the plane to the shape.
RUBBLE_FN ContactManifold collideWithPlaneItem(HullArrays arrays, float4 plane, HullShape other,
                                               RigidTransform t, float margin) {
    const float4 normal = faceNormalItem(plane);
    if (other.kind == RUBBLE_SHAPE_SPHERE)
        return collidePlaneSphereItem(normal, plane.w, t.translation, other.radius, margin);
    if (other.kind != RUBBLE_SHAPE_HULL) return emptyContactsItem();
    // The plane in the hull's frame: n_h = R^T n, d_h = d - n . t.
    const float4 n = transformRotateInverse(t, normal);
    const float d = plane.w - dot3(normal, t.translation);
    return contactsToWorldItem(collidePlaneHullItem(n, d, hullOfItem(arrays, other), margin), t,
                               0);
}

// Capsule `cap` at tc against `other` at to, in the world frame, normal from the capsule to the
// other shape (host/collision/capsule_contact.cpp's collideCapsuleWith).
RUBBLE_FN ContactManifold collideCapsuleWithItem(HullArrays arrays, HullShape cap,
                                                 RigidTransform tc, HullShape other,
                                                 RigidTransform to, float margin) {
    const CapsuleSegment s = capsuleSegmentItem(cap.halfHeight, tc);
    if (other.kind == RUBBLE_SHAPE_CAPSULE)
        return collideCapsulesItem(s, cap.radius, capsuleSegmentItem(other.halfHeight, to),
                                   other.radius, margin);
    if (other.kind == RUBBLE_SHAPE_SPHERE)
        return collideCapsuleSphereItem(s, cap.radius, to.translation, other.radius, margin);
    if (other.kind == RUBBLE_SHAPE_PLANE) {
        const float4 plane = worldPlaneItem(other, to);
        ContactManifold m =
            collidePlaneCapsuleItem(vec4(plane.x, plane.y, plane.z), plane.w, s, cap.radius, margin);
        m.normal = negate4(m.normal);
        return m;
    }
    // The segment in the hull's frame; the contacts back in the world's.
    CapsuleSegment inHull;
    inHull.p0 = transformApplyInverse(to, s.p0);
    inHull.p1 = transformApplyInverse(to, s.p1);
    return contactsToWorldItem(
        collideHullCapsuleItem(hullOfItem(arrays, other), inHull, cap.radius, margin), to, 1);
}

// Collides shape a at transform ta with shape b at tb, body to world, clipping
// hull faces in the caller's buffers. Hull pairs read and update the cache; other pairs leave it
// alone. The result is in the world frame, normal from a to b; a and b are left 0 for the
// caller.
RUBBLE_FN ContactManifold collideShapesClippingInItem(HullArrays arrays, HullShape a,
                                                      RigidTransform ta, HullShape b,
                                                      RigidTransform tb, PairCache* cache,
                                                      float margin, ClipBuffers buffers) {
    const int hullA = a.kind == RUBBLE_SHAPE_HULL, hullB = b.kind == RUBBLE_SHAPE_HULL;
    if (a.kind == RUBBLE_SHAPE_CAPSULE)
        return collideCapsuleWithItem(arrays, a, ta, b, tb, margin);
    if (b.kind == RUBBLE_SHAPE_CAPSULE) {
        ContactManifold r = collideCapsuleWithItem(arrays, b, tb, a, ta, margin);
        r.normal = negate4(r.normal);
        return r;
    }
    if (hullA && hullB) {
        const HullContact hc =
            collideHullsCachedItem(hullOfItem(arrays, a), hullOfItem(arrays, b),
                                   transformRelative(ta, tb), cache, margin, buffers);
        return contactsToWorldItem(hc.contacts, ta, 0);
    }
    if (a.kind == RUBBLE_SHAPE_PLANE && b.kind != RUBBLE_SHAPE_PLANE)
        return collideWithPlaneItem(arrays, worldPlaneItem(a, ta), b, tb, margin);
    if (b.kind == RUBBLE_SHAPE_PLANE && a.kind != RUBBLE_SHAPE_PLANE) {
        ContactManifold r = collideWithPlaneItem(arrays, worldPlaneItem(b, tb), a, ta, margin);
        r.normal = negate4(r.normal);
        return r;
    }
    if (a.kind == RUBBLE_SHAPE_SPHERE && b.kind == RUBBLE_SHAPE_SPHERE)
        return collideSpheresItem(ta.translation, a.radius, tb.translation, b.radius, margin);
    if (hullA && b.kind == RUBBLE_SHAPE_SPHERE) {
        const ContactManifold inShape = collideHullSphereItem(
            hullOfItem(arrays, a), transformApplyInverse(ta, tb.translation), b.radius, margin);
        return contactsToWorldItem(inShape, ta, 0);
    }
    if (a.kind == RUBBLE_SHAPE_SPHERE && hullB) {
        const ContactManifold inShape = collideHullSphereItem(
            hullOfItem(arrays, b), transformApplyInverse(tb, ta.translation), a.radius, margin);
        return contactsToWorldItem(inShape, tb, 1);
    }
    return emptyContactsItem();
}

// collideShapesClippingInItem with buffers in private memory, for hulls whose faces have at
// most RUBBLE_HULL_MAX_FACE_VERTICES vertices (the device's; host/gpu/hull_data.cpp refuses
// larger).
RUBBLE_FN ContactManifold collideShapesItem(HullArrays arrays, HullShape a, RigidTransform ta,
                                            HullShape b, RigidTransform tb, PairCache* cache,
                                            float margin) {
    ClipVertex polygon[RUBBLE_CLIP_CAPACITY], scratch[RUBBLE_CLIP_CAPACITY];
    LocalContact candidates[RUBBLE_CLIP_CAPACITY];
    ClipBuffers buffers;
    buffers.polygon = polygon;
    buffers.scratch = scratch;
    buffers.candidates = candidates;
    return collideShapesClippingInItem(arrays, a, ta, b, tb, cache, margin, buffers);
}

RUBBLE_SHARED_END
