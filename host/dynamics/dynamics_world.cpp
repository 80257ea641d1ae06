// host/dynamics/dynamics_world.cpp: CPU stages 5 and 6 over a world's arrays.
#include "host/dynamics/dynamics_world.h"

#include "host/world/world_state.h"

namespace rubble {

void runBuildContactRows(WorldState&) {}
void runSolveVelocities(WorldState&) {}
void runSolvePositions(WorldState&) {}
void runUpdateSleep(WorldState&) {}

} // namespace rubble
