// host/world/backend_check.cpp: the combinations of backend, collision method and solver.
#include "host/world/backend_check.h"

#include <string>

namespace rubble {

Status checkBackendCombination(const Scene& scene) {
    const SimulationOptions& sim = scene.simulation;
    if (sim.backend != Backend::OpenCl) return {};
    const std::string field = scene.file + ": simulation.";
    if (sim.collisionMethod() == CollisionMethod::Sat)
        return makeError(ErrorKind::NotSupported, field + "collision.method",
                         "sat collision runs on the cpu backend only; the opencl backend finds "
                         "contacts with particles (--collision particles)");
    if (sim.solver.type == SolverType::Pgs || sim.solver.type == SolverType::Lemke)
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "the " + std::string(toString(sim.solver.type)) +
                             " solver runs on the cpu backend only; the opencl backend solves "
                             "with jacobi or lcp-jacobi (--solver jacobi)");
    if (!scene.joints.empty())
        return makeError(ErrorKind::NotSupported, scene.joints[0].where,
                         "joints run on the cpu backend only (the opencl backend has no joint "
                         "rows)");
    return {};
}

} // namespace rubble
