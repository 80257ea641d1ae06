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

/// Collides hull a with hull b (b's pose in a's frame). Points are made while the hulls are
/// closer than `margin` (m). A face contact clips the incident face (the face of the other hull
/// most anti-parallel to the reference face) against the side planes of the reference face,
/// keeps the points below the reference plane plus margin, and at most four of them; an edge
/// contact is the midpoint of the closest points of the two edges. Faces win over edges, and
/// last step's face owner (`hint`) over the other, unless the other is clearly shallower, so
/// that feature ids stay put while bodies rest.
HullContact collideHulls(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                         float margin = kContactMargin, const SatHint& hint = {});

} // namespace rubble
