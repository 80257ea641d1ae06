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
    std::vector<Aabb> boxes;                 ///< per body, this step, grown by margin and reach
    std::vector<float> reach;                ///< per body: how far any of its points can move this step, m
    std::vector<float> spin;                 ///< per body: the part of reach due to turning, m
    std::vector<std::uint8_t> flags;         ///< per body, BroadPhaseFlag
    std::vector<PlaneProxy> planes;
    BroadPhaseScratch broadPhase;
};

/// Stage broadPhase. reads: poses, velocities, shapes, masses (static and asleep flags)
/// writes: pairs (sorted, a < b, no pair of two static or sleeping bodies), stats.pairCount.
/// Boxes are grown by kContactMargin plus the body's reach this step, (|v| + |omega| r) dt, so
/// that the narrow phase sees every pair that could touch before the next step (speculative
/// contacts: a fast body meets what lies in its path instead of tunnelling through it).
void runBroadPhase(WorldState& s);

/// Stage narrowPhase. reads: pairs, poses, shapes, collision cache, reach   writes: manifolds (in
/// pair order, pairs without contacts left out), collision cache, stats.contactCount,
/// stats.largestPenetration. A pair's margin is kContactMargin plus how much closer the bodies
/// can come this step (relative translation plus turning): contacts up to that gap come out with
/// negative depth, and the solver lets them close only that far.
void runNarrowPhase(WorldState& s);

} // namespace rubble
