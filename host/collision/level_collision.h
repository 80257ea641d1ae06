// host/collision/level_collision.h: a body against a static mesh's triangles in stage
// narrowPhase of the CPU pipeline (SatCollision): the triangles under the body's box from the
// mesh's hierarchy, each collided (triangle_contact.h), their contacts grouped by normal and
// each group reduced to a manifold of at most four points (rubble/shared/level_contact.h, whose
// device twin keeps the group with the deepest point). Each pair's triangles under a grown box
// are kept between steps (LevelCandidateCache) while the body's box stays inside it; with
// recycle_contacts its manifolds are kept too (LevelManifoldCache) and stand for new ones while
// the body has hardly moved.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/collision/broad_phase.h"
#include "host/collision/triangle_contact.h"
#include "host/geometry/shape.h"
#include "rubble/shared/clip.h"
#include "rubble/shared/contact_recycling.h"
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

/// How far a level pair's kept box reaches past the body's box on every side, in the level's
/// frame, m: the body may move (or turn) this much before its pair walks the hierarchy again.
/// Larger keeps more triangles to filter each step, smaller walks more often; a falling crate
/// moves about 0.16 m a step at 10 m/s, one at rest not at all.
inline constexpr float kLevelCandidateMargin = 0.1f;

/// The world box `otherBox` as a box in the frame of the level placed at `levelAt`: what the
/// level's hierarchy is queried with.
BvhBox levelQueryBox(const shared::RigidTransform& levelAt, const Aabb& otherBox);

/// The triangles under each (body, static level) pair's box, kept between steps: a pair's
/// hierarchy query is made for the body's box grown by kLevelCandidateMargin (level frame) and
/// reused while this step's box stays inside the grown one, so that any translation or rotation
/// that moves a side of the box by more than the margin walks the hierarchy again. The triangles
/// handed out are those of the grown box whose own boxes overlap this step's box, ascending:
/// exactly what TriangleBvh::query gives for it, so contacts and trajectories do not change.
/// Pairs not seen in a step (separated, asleep) are forgotten.
class LevelCandidateCache {
  public:
    /// Starts a step: the pairs given from here on replace last step's.
    void beginStep();
    /// The triangles of `level` whose boxes overlap `query` (the body's box in the level's
    /// frame), ascending, into `out`. Pairs must come in ascending order within a step.
    void candidates(const BodyPair& pair, const LevelMesh& level, const BvhBox& query,
                    std::vector<std::uint32_t>& out);
    /// Carries `pair`'s kept triangles to the next step untouched, for a pair that does not
    /// collide its triangles this step (its manifolds are recycled). Same order as candidates.
    void carry(const BodyPair& pair);
    /// Ends a step: its pairs are kept for the next.
    void endStep();
    /// Forgets every pair (they name bodies by index).
    void clear();

    /// This step's pairs that kept last step's triangles, and those that walked the hierarchy.
    std::uint32_t reused() const { return reused_; }
    std::uint32_t queried() const { return queried_; }
    /// Pairs kept for the next step (after endStep).
    std::size_t size() const { return entries_.size(); }
    /// The grown box kept for `pair` (after endStep), or nullptr.
    const BvhBox* keptBox(const BodyPair& pair) const;

  private:
    struct Entry {
        BodyPair pair;
        BvhBox box;              ///< the grown box queried, level frame
        std::uint32_t first = 0; ///< its triangles in the pool, ascending
        std::uint32_t count = 0;
    };
    static bool contains(const BvhBox& outer, const BvhBox& inner);

    std::vector<Entry> entries_, next_;                    ///< sorted by pair
    std::vector<std::uint32_t> triangles_, nextTriangles_; ///< the entries' triangles
    std::size_t cursor_ = 0;
    std::uint32_t reused_ = 0, queried_ = 0;
};

/// With recycle_contacts (StepParams::recycleContacts), each (body, static level) pair's
/// manifolds, kept in the frames of the level and of the body as a hull pair keeps its one
/// (shared::RecycledManifold per manifold, the level as body a). While no point of the body can
/// have moved by more than RUBBLE_RECYCLE_DISTANCE against the level since they were made (its
/// origin's move plus the turn's chord times its bounding radius, in the level's frame), they
/// stand for new ones: each point keeps its surface point on the level and on the body, its
/// separation is recomputed along the normal kept in the level's frame, and it is placed as the
/// triangle test places it (from the body's point where the triangle's face clipped the body,
/// from the triangle's where a face of the body clipped the triangle, midway otherwise). The
/// pair's margin may be at most RUBBLE_RECYCLE_DISTANCE wider than the one the manifolds were
/// made with (a triangle point left out then is still 3.5 mm clear at the end of the step, as
/// for a hull pair; the margin of a body resting on a level holds the step's gravity, g dt^2),
/// and they are recycled at most RUBBLE_RECYCLE_MAX_AGE steps in a row. Pairs not seen in a
/// step are forgotten; a pair whose last collision gave no contact keeps nothing.
class LevelManifoldCache {
  public:
    /// Starts a step: the pairs given from here on replace last step's.
    void beginStep();
    /// When `pair` may recycle last step's manifolds with the body at `bodyInLevel` (its pose
    /// in the level's frame; the level at `levelAt`), appends them rebuilt to `out` (world
    /// frame, normals from the level to the body, points beyond `margin` left out), keeps them
    /// for the next step and returns true; otherwise (nothing kept, past a limit, every point
    /// beyond the margin) leaves `out` alone and returns false. `bodyRadius` is the body's
    /// bounding radius (m). Pairs must come in ascending order within a step.
    bool recycle(const BodyPair& pair, const shared::RigidTransform& levelAt,
                 const shared::RigidTransform& bodyInLevel, float bodyRadius, float margin,
                 std::vector<shared::ContactManifold>& out);
    /// Keeps the manifolds the triangles just gave `pair` with `margin` (world frame, normals
    /// from the level to the body, as collideLevelTriangles makes them) with the body at
    /// `bodyInLevel`.
    void keep(const BodyPair& pair, const shared::RigidTransform& levelAt,
              const shared::RigidTransform& bodyInLevel, float margin,
              std::span<const shared::ContactManifold> manifolds);
    /// Ends a step: its pairs are kept for the next.
    void endStep();
    /// Forgets every pair (they name bodies by index).
    void clear();

    /// This step's pairs whose manifolds were recycled.
    std::uint32_t recycled() const { return recycled_; }
    /// Pairs kept for the next step (after endStep).
    std::size_t size() const { return entries_.size(); }

  private:
    struct Entry {
        BodyPair pair;
        std::uint32_t first = 0; ///< its manifolds in the pool
        std::uint32_t count = 0;
        float margin = 0.0f; ///< the pair's margin when they were made, m
    };

    std::vector<Entry> entries_, next_; ///< sorted by pair
    std::vector<shared::RecycledManifold> manifolds_, nextManifolds_;
    std::size_t cursor_ = 0;
    std::uint32_t recycled_ = 0;
};

/// The static level mesh at `levelAt` against `other` (a box, convex hull, mesh hull, sphere or
/// capsule) at `otherAt`, whose world box (grown by its margin and reach) is `otherBox`:
/// manifolds appended to `out`, in the world frame, normals from the level to the other body,
/// features naming triangles (a and b left for the caller). Planes and other level meshes give
/// nothing.
void collideLevel(const LevelMesh& level, const shared::RigidTransform& levelAt, const Shape& other,
                  const shared::RigidTransform& otherAt, const Aabb& otherBox, float margin,
                  LevelScratch& scratch, std::vector<shared::ContactManifold>& out);

/// collideLevel against the given triangles of the level (ascending; those under the other
/// body's box, as levelQueryBox and the hierarchy or a LevelCandidateCache find them).
void collideLevelTriangles(const LevelMesh& level, const shared::RigidTransform& levelAt,
                           const Shape& other, const shared::RigidTransform& otherAt,
                           std::span<const std::uint32_t> triangles, float margin,
                           LevelScratch& scratch, std::vector<shared::ContactManifold>& out);

/// Up to four of the points (their indices into `contacts`, from `group`), spanning the largest
/// area (reduceLevelGroupItem).
void reduceContacts(const std::vector<TriangleContact>& contacts,
                    const std::vector<std::uint32_t>& group, std::vector<std::uint32_t>& kept);

} // namespace rubble
