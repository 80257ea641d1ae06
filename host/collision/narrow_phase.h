// host/collision/narrow_phase.h: CPU stage narrowPhase for one pair: dispatch by shape type to
// the hull (SAT and clipping), sphere and plane contacts, results brought to the world frame.
#pragma once

#include "host/collision/contact_set.h"
#include "host/collision/hull_contact.h"
#include "host/collision/hull_data.h"
#include "host/collision/sat.h"
#include "host/collision/transform.h"
#include "host/geometry/shape.h"

namespace rubble {

/// The contacts of one pair in the world frame.
struct PairContact {
    ContactSet contacts; ///< world positions, normal from a to b
};

/// Collides shape a at transform ta with shape b at tb (body to world). Hull pairs read and
/// update `cache` (hull_contact.h); other pairs leave it alone. Plane against plane gives
/// nothing.
PairContact collideShapes(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                          HullPairCache& cache, float margin = kContactMargin);

/// The same without a cache: the full test every time.
PairContact collideShapes(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                          float margin = kContactMargin);

} // namespace rubble
