// host/collision/level_collision.h: a body against a static mesh's triangles in stage
// narrowPhase of the CPU pipeline (SatCollision): the triangles under the body's box from the
// mesh's hierarchy, each collided (triangle_contact.h), their contacts grouped by normal and
// each group reduced to a manifold of at most four points.
#pragma once

#include <cstdint>
#include <vector>

#include "host/collision/broad_phase.h"
#include "host/collision/triangle_contact.h"
#include "host/geometry/shape.h"
#include "rubble/shared/clip.h"
#include "rubble/shared/hull.h"

namespace rubble {

/// Arrays one pair's level collision reuses.
struct LevelScratch {
    std::vector<std::uint32_t> triangles;
    std::vector<TriangleContact> contacts;
    std::vector<std::uint32_t> group, kept;
    std::vector<std::uint8_t> taken;
    PlacedHull hull;
};

/// Contacts whose normals have a cosine above this (about 5.7 degrees apart) share a manifold:
/// the facets of a curved surface under one body give it one or two manifolds, not one each.
inline constexpr float kSameNormalCosine = 0.995f;

/// The static level mesh at `levelAt` against `other` (a box, convex hull, mesh hull, sphere or
/// capsule) at `otherAt`, whose world box (grown by its margin and reach) is `otherBox`:
/// manifolds appended to `out`, in the world frame, normals from the level to the other body,
/// features naming triangles (a and b left for the caller). Planes and other level meshes give
/// nothing.
void collideLevel(const LevelMesh& level, const shared::RigidTransform& levelAt, const Shape& other,
                  const shared::RigidTransform& otherAt, const Aabb& otherBox, float margin,
                  LevelScratch& scratch, std::vector<shared::ContactManifold>& out);

/// Up to four of the points (their indices into `contacts`, from `group`), spanning the largest
/// area: the deepest, the furthest from it, the furthest from their line, and the one that adds
/// most area. Points within 1e-5 m of a kept one are left out.
void reduceContacts(const std::vector<TriangleContact>& contacts,
                    const std::vector<std::uint32_t>& group, std::vector<std::uint32_t>& kept);

} // namespace rubble
