// host/dynamics/dynamics_world.h: CPU stages 5 and 6 on a whole world (contact and joint rows,
// the velocity solve), the position correction after stage 7, and islands and sleeping.
#pragma once

namespace rubble {

struct WorldState;

/// What the solver keeps between steps (impulses for warm starting, sleep timers).
struct SolverCache {};

/// Stage buildContactRows. reads: manifolds, poses, masses, materials, joints, solver cache
/// writes: constraint rows
void runBuildContactRows(WorldState& s);

/// Stage solve. reads: rows   writes: velocities, impulses, stats.solverResidual
void runSolveVelocities(WorldState& s);

/// After integratePositions: position-level correction of joints. writes: poses
void runSolvePositions(WorldState& s);

/// Islands and sleeping. reads: velocities, manifolds, joints   writes: masses[i].flags
void runUpdateSleep(WorldState& s);

} // namespace rubble
