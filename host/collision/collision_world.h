// host/collision/collision_world.h: CPU stages 3 and 4 on a whole world (SAT method): the broad
// phase fills WorldState::pairs, the narrow phase WorldState::manifolds.
#pragma once

#include <cstdint>
#include <vector>

#include "host/collision/broad_phase.h"
#include "host/collision/contact.h"
#include "host/collision/hull_contact.h"
#include "host/collision/transform.h"

namespace rubble {

struct WorldState;

/// A hull pair's axis or contact feature, kept for the next step.
struct CachedFeature {
    BodyPair pair;
    HullPairCache cache;
};

/// What the collision stages keep between steps (frame coherence), and their reused arrays.
struct CollisionCache {
    /// Last step's features, sorted by pair: the next narrow phase tests them first.
    std::vector<CachedFeature> features;
    std::vector<CachedFeature> nextFeatures; ///< being filled; swapped with features
    std::vector<Transform> transforms;       ///< per body, this step
    std::vector<Aabb> boxes;                 ///< per body, this step, grown by the margin
    std::vector<std::uint8_t> flags;         ///< per body, BroadPhaseFlag
    std::vector<PlaneProxy> planes;
    BroadPhaseScratch broadPhase;
};

/// Stage broadPhase. reads: poses, shapes, masses (static and asleep flags)   writes: pairs
/// (sorted, a < b, no pair of two static or sleeping bodies), stats.pairCount. Boxes are grown
/// by kContactMargin so that the narrow phase sees every pair it could make contacts for.
void runBroadPhase(WorldState& s);

/// Stage narrowPhase. reads: pairs, poses, shapes, collision cache   writes: manifolds (in pair
/// order, pairs without contacts left out), collision cache, stats.contactCount,
/// stats.largestPenetration
void runNarrowPhase(WorldState& s);

} // namespace rubble
