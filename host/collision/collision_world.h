// host/collision/collision_world.h: CPU stages 3 and 4 on a whole world (SAT method): the broad
// phase fills WorldState::pairs, the narrow phase WorldState::manifolds.
#pragma once

namespace rubble {

struct WorldState;

/// What the collision stages keep between steps (frame coherence).
struct CollisionCache {};

/// Stage broadPhase. reads: poses, shapes   writes: pairs (sorted, a < b, no static-static)
void runBroadPhase(WorldState& s);

/// Stage narrowPhase. reads: pairs, poses, shapes   writes: manifolds, stats.contactCount,
/// stats.largestPenetration
void runNarrowPhase(WorldState& s);

} // namespace rubble
