// host/collision/collision_world.cpp: CPU stages 3 and 4 over a world's arrays.
#include "host/collision/collision_world.h"

#include "host/world/world_state.h"

namespace rubble {

void runBroadPhase(WorldState& s) { s.pairs.clear(); }

void runNarrowPhase(WorldState& s) { s.manifolds.clear(); }

} // namespace rubble
