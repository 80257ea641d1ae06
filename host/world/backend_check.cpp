// host/world/backend_check.cpp: the combinations of backend, collision method and solver.
#include "host/world/backend_check.h"

#include <string>

#include "host/world/offload.h"

namespace rubble {

Status checkBackendCombination(const Scene& scene) {
    const SimulationOptions& sim = scene.simulation;
    if (sim.backend != Backend::OpenCl) return {};
    const std::string field = scene.file + ": simulation.";
    if (sim.collisionMethod() == CollisionMethod::Sat)
        return makeError(ErrorKind::NotSupported, field + "collision.method",
                         "sat collision runs on the cpu backend only; the opencl backend finds "
                         "contacts with particles (--collision particles)");
    // With a debris set, pgs is the CPU bodies' solver and the set takes jacobi (offload.h).
    const SolverType device = deviceSolver(scene);
    if (device == SolverType::Pgs || device == SolverType::Lemke)
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "the " + std::string(toString(device)) +
                             " solver runs on the cpu backend only; the opencl backend solves "
                             "with jacobi or lcp-jacobi (--solver jacobi), or, in a scene with "
                             "a debris set, steps the set with jacobi and the rest with pgs");
    // Jointed bodies stay on the CPU; a joint on a debris body cannot.
    const std::vector<std::uint8_t> onDevice = deviceBodies(scene);
    for (const JointDesc& j : scene.joints) {
        const std::uint32_t d = onDevice[j.a] ? j.a : j.b;
        if (!onDevice[d]) continue;
        return makeError(ErrorKind::NotSupported, j.where,
                         "joins debris body \"" + scene.bodies[d].name +
                             "\": the debris set steps on the OpenCL device, which has no joint "
                             "rows (leave the body out of the debris set)");
    }
    return {};
}

} // namespace rubble
