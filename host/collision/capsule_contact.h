// host/collision/capsule_contact.h: contacts of capsules with planes, spheres, capsules and
// convex hulls in stage narrowPhase of the CPU pipeline (SatCollision): closest points of
// segments (Ericson 5.1.9), separating axes of a hull against the capsule's segment, and the
// segment clipped to a hull face for a capsule that lies on it (two points).
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "host/geometry/shape.h"
#include "rubble/shared/clip.h"
#include "rubble/shared/hull.h"

namespace rubble {

/// A capsule's core: the segment from p0 to p1, m.
struct Segment {
    glm::vec3 p0{0.0f}, p1{0.0f};
};

/// The closest points of two segments: s and t along a and b (0..1), and the points.
struct SegmentClosest {
    float s = 0.0f, t = 0.0f;
    glm::vec3 onA{0.0f}, onB{0.0f};
};

/// Closest points of segments a and b (Ericson, "Real-Time Collision Detection", 5.1.9); for
/// parallel segments, one pair of the closest.
SegmentClosest closestSegmentPoints(const Segment& a, const Segment& b);

/// The capsule's segment at a body's transform, world frame.
Segment capsuleSegment(float halfHeight, const shared::RigidTransform& t);

/// A plane (solid below dot(n, x) = offset) and a capsule: one point per end of the segment
/// within the margin; the normal is the plane's.
shared::ContactManifold collidePlaneCapsule(glm::vec3 n, float offset, const Segment& s,
                                            float radius, float margin);

/// A capsule and a sphere; the normal points from the capsule to the sphere.
shared::ContactManifold collideCapsuleSphere(const Segment& s, float radius, glm::vec3 centre,
                                             float sphereRadius, float margin);

/// Two capsules; the normal points from a to b. Nearly parallel segments that overlap along
/// their length touch at the two ends of the overlap.
shared::ContactManifold collideCapsules(const Segment& a, float ra, const Segment& b, float rb,
                                        float margin);

/// A convex hull and a capsule whose segment is in the hull's frame; the result is in the hull's
/// frame, normal from the hull to the capsule. The separating axes are the hull's face normals
/// and the cross products of its edges with the segment; a capsule whose closest feature is a
/// face (lying on it) touches at the segment clipped to that face, up to two points, otherwise
/// at one point.
shared::ContactManifold collideHullCapsule(const HalfEdgeMesh& hull, const Segment& s,
                                           float radius, float margin);

/// A pair of which at least one shape is a capsule, at the bodies' transforms: the manifold in
/// the world frame with its normal from a to b; std::nullopt when neither shape is a capsule.
std::optional<shared::ContactManifold> collideCapsulePair(const Shape& a,
                                                          const shared::RigidTransform& ta,
                                                          const Shape& b,
                                                          const shared::RigidTransform& tb,
                                                          float margin);

} // namespace rubble
