// host/dynamics/jacobi_solvers.h: CPU stages 5 and 6 for the solvers other than PGS (jacobi,
// lcp-jacobi, lemke), on the contacts of either collision method.
#pragma once

namespace rubble {

struct WorldState;

/// Stage buildContactRows for the non-PGS solvers: contact points (particle contacts, or the
/// SAT manifolds' points) into rows. reads: contacts, poses, velocities, masses, materials
/// writes: s.jacobi
void runBuildSolverRows(WorldState& s);

/// Stage solve for the non-PGS solvers. reads: s.jacobi, velocitiesBeforeSolve   writes:
/// velocities, stats.solverResidual
void runSolveRows(WorldState& s);

} // namespace rubble
