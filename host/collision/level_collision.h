// host/collision/level_collision.h: a body against a static mesh's triangles in stage
// narrowPhase of the CPU pipeline (SatCollision): the triangles under the body's box from the
// mesh's hierarchy, each collided (triangle_contact.h), their contacts grouped by normal and
// each group reduced to a manifold of at most four points (rubble/shared/level_contact.h, whose
// device twin keeps the group with the deepest point).
#pragma once

#include <cstdint>
#include <vector>

#include "host/collision/broad_phase.h"
#include "host/collision/triangle_contact.h"
#include "host/geometry/shape.h"
#include "rubble/shared/clip.h"
#include "rubble/shared/hull.h"
#include "rubble/shared/level_contact.h"

namespace rubble {

/// Arrays one pair's level collision reuses.
struct LevelScratch {
    std::vector<std::uint32_t> triangles;
    std::vector<shared::TriangleContact> contacts;
    std::vector<std::uint32_t> group, taken;
    PlacedHull hull;
};

/// The static level mesh at `levelAt` against `other` (a box, convex hull, mesh hull, sphere or
/// capsule) at `otherAt`, whose world box (grown by its margin and reach) is `otherBox`:
/// manifolds appended to `out`, in the world frame, normals from the level to the other body,
/// features naming triangles (a and b left for the caller). Planes and other level meshes give
/// nothing.
void collideLevel(const LevelMesh& level, const shared::RigidTransform& levelAt, const Shape& other,
                  const shared::RigidTransform& otherAt, const Aabb& otherBox, float margin,
                  LevelScratch& scratch, std::vector<shared::ContactManifold>& out);

/// Up to four of the points (their indices into `contacts`, from `group`), spanning the largest
/// area (reduceLevelGroupItem).
void reduceContacts(const std::vector<TriangleContact>& contacts,
                    const std::vector<std::uint32_t>& group, std::vector<std::uint32_t>& kept);

} // namespace rubble
