// host/collision/sat_collision.h: CPU stages broadPhase and narrowPhase of the reference
// pipeline (SAT method): body boxes and planes into the broad phase, pairs through the narrow
// phase (rubble/shared/narrow_phase.h, over the flattened hulls of hull_data.h) into manifolds,
// with frame coherence between steps.
#pragma once

#include <cstdint>
#include <vector>

#include "host/collision/broad_phase.h"
#include "host/collision/collision_stage.h"
#include "host/collision/hull_data.h"
#include "host/collision/level_collision.h"
#include "rubble/shared/contact_recycling.h"

namespace rubble {

/// A hull pair's axis or contact feature, kept for the next step.
struct CachedFeature {
    BodyPair pair;
    shared::PairCache cache;
};

/// What the SAT stages keep between steps (frame coherence), and their reused arrays.
struct CollisionCache {
    /// Last step's features, sorted by pair: the next narrow phase tests them first.
    std::vector<CachedFeature> features;
    std::vector<CachedFeature> nextFeatures; ///< being filled; swapped with features
    /// With StepParams::recycleContacts, each feature's manifold for recycling (same index as
    /// features); empty without.
    std::vector<shared::RecycledManifold> recycled;
    std::vector<shared::RecycledManifold> nextRecycled; ///< being filled; swapped with recycled
    std::vector<shared::RigidTransform> transforms; ///< per body, this step's broad phase
    std::vector<Aabb> boxes;                 ///< per body, this step, grown by margin and reach
    std::vector<float> spin; ///< per body: how far its turning can move any of its points, m
    std::vector<std::uint8_t> flags; ///< per body, BroadPhaseFlag
    std::vector<PlaneProxy> planes;
    BroadPhaseScratch broadPhase;
    HullData hulls;                          ///< the scene's shapes, flattened
    const Shape* hullsOf = nullptr;          ///< the shapes `hulls` was made from
    ClipSpace clip;                          ///< for the hulls' largest face
    LevelScratch level;                      ///< pairs with a static mesh
    LevelCandidateCache levelCandidates;     ///< their triangles, kept between steps
    LevelManifoldCache levelRecycled;        ///< their manifolds, with recycleContacts
    std::vector<shared::ContactManifold> levelManifolds;
};

/// The SAT collision method.
class SatCollision final : public CollisionStage {
  public:
    explicit SatCollision(ContactForm form) : form_(form) {}

    /// reads: poses, velocities, masses (static and asleep flags), shapes, joined
    /// writes: pairs (sorted, a < b, no pair of two static or sleeping bodies, none of two joined
    /// bodies, none of two bodies of infinite mass; a moving kinematic body pairs with sleeping
    /// ones). Boxes are grown by RUBBLE_CONTACT_MARGIN plus the body's reach this step,
    /// (|v| + |omega| r) dt, so that the narrow phase sees every pair that could touch before the
    /// next step (speculative contacts: a fast body meets what lies in its path instead of
    /// tunnelling through it).
    Status broadPhase(const CollisionScene& scene, BodiesView bodies, const StepParams& params,
                      StepContacts& out) override;
    /// reads: pairs, velocities, the broad phase's transforms and spins, the cache   writes:
    /// manifolds (in pair order, pairs without contacts left out; as points when the solver reads
    /// points), the cache. A pair's margin is RUBBLE_CONTACT_MARGIN plus how much closer the
    /// bodies can come this step (relative translation plus turning): contacts up to that gap
    /// come out with negative depth, and the solver lets them close only that far. A static body
    /// whose shape has a LevelMesh collides by its triangles (level_collision.h), one manifold
    /// per group of contacts sharing a normal, over the triangles the cache kept for the pair
    /// (LevelCandidateCache; the same triangles as a fresh query). With
    /// StepParams::recycleContacts a hull pair that moved little against itself keeps last
    /// step's manifold (rubble/shared/contact_recycling.h), and a level pair its manifolds
    /// (LevelManifoldCache).
    Status narrowPhase(const CollisionScene& scene, BodiesView bodies,
                       const StepParams& params, StepContacts& out) override;
    /// The manifolds' points (manifoldsToContacts).
    void contactPoints(const StepContacts& contacts,
                       std::vector<shared::ParticleContact>& points) const override;
    /// Forgets the cached features and level triangles and manifolds (they name bodies by index)
    /// and flattens
    /// the shapes.
    Status rebuild(const CollisionScene& scene, BodiesView bodies, float particleSpacing) override;

    const CollisionCache& cache() const { return cache_; }

  private:
    ContactForm form_;
    CollisionCache cache_;
};

/// SAT manifolds as contact points for the row builder of the jacobi family (the feature id in
/// featureB, body a in particleA).
void manifoldsToContacts(std::span<const Manifold> manifolds,
                         std::vector<shared::ParticleContact>& contacts);

} // namespace rubble
