// host/dynamics/jacobi_solvers.cpp: the choice among the CPU twins of the device solvers.
#include "host/dynamics/jacobi_solvers.h"

#include "host/dynamics/jacobi.h"
#include "host/world/world_state.h"

namespace rubble {

void runBuildSolverRows(WorldState& s) { runBuildJacobiRows(s); }

void runSolveRows(WorldState& s) {
    switch (s.options.solver.type) {
    case SolverType::Jacobi:
    case SolverType::Pgs:
    case SolverType::LcpJacobi:
    case SolverType::Lemke:
        runSolveJacobi(s);
        return;
    }
}

} // namespace rubble
