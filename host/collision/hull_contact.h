// host/collision/hull_contact.h: the contact manifold of two convex hulls, part of CPU stage
// narrowPhase: SAT (sat.h), then a clipped face contact or an edge contact (Gregorius, "Robust
// Contact Creation for Physics Simulations", GDC 2015; physics report 3.4). Pure.
#pragma once

#include "host/collision/contact_set.h"
#include "host/collision/sat.h"

namespace rubble {

/// The contacts of two hulls, or the axis that separates them.
struct HullContact {
    bool separated = false;
    ContactSet contacts; ///< in A's frame, normal from A to B
    SatHint feature;     ///< the separating axis, or the feature the contacts came from
};

/// What a hull pair keeps from one step to the next (frame coherence).
struct HullPairCache {
    SatHint feature;       ///< last step's separating axis or contact feature
    Transform reference;   ///< b's pose in a's frame when the full test last ran
    bool reusable = false; ///< feature and reference come from a full test
};

/// While b's pose in a's frame stays within these of the cache's reference (m, and per entry of
/// the rotation matrix, about 0.6 degrees), the cached feature is reused without a full SAT.
inline constexpr float kReuseDistance = 1e-3f;
inline constexpr float kReuseRotation = 0.01f;

/// Collides hull a with hull b (b's pose in a's frame). Points are made while the hulls are
/// closer than `margin` (m). A face contact clips the incident face (the face of the other hull
/// most anti-parallel to the reference face) against the side planes of the reference face,
/// keeps the points below the reference plane plus margin, and at most four of them; an edge
/// contact is the midpoint of the closest points of the two edges. Faces win over edges, and
/// last step's face owner (`hint`) over the other, unless the other is clearly shallower, so
/// that feature ids stay put while bodies rest.
HullContact collideHulls(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                         float margin = kContactMargin, const SatHint& hint = {});

/// Contacts from a known feature, skipping the search: a face's separation from one support
/// query, then the same clipping; an edge pair's from the support points along its axis. For
/// a pair whose relative pose has barely moved since the feature was found. A feature whose
/// separation exceeds the margin still separates the hulls (separated = true).
HullContact collideHullsFromFeature(const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                                    const Transform& bInA, const SatHint& feature,
                                    float margin = kContactMargin);

/// Collides with the pair's cache: the feature is reused while b's pose in a's frame stays
/// within kReuseDistance and kReuseRotation of the reference (and a cached edge pair's axis has
/// turned by less than half a degree and still spans a face of the Minkowski difference: its
/// edges are the support features along it), else the full test runs and becomes the new
/// reference.
HullContact collideHullsCached(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                               HullPairCache& cache, float margin = kContactMargin);

} // namespace rubble
