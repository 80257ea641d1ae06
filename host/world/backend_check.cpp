// host/world/backend_check.cpp: the combinations of backend, collision method and solver.
#include "host/world/backend_check.h"

#include <string>

#include "host/world/offload.h"

namespace rubble {

Status checkBackendCombination(const Scene& scene) {
    const SimulationOptions& sim = scene.simulation;
    const std::string field = scene.file + ": simulation.";
    // Joint rows live in PGS; the other solvers take contact rows only. On the cpu backend every
    // body steps with the scene's solver, so a joint there needs pgs (on opencl jointed bodies
    // step on the CPU with PGS whatever the device's solver is).
    if (sim.backend != Backend::OpenCl && sim.solver.type != SolverType::Pgs &&
        !scene.joints.empty()) {
        std::string first = scene.joints.front().where;
        if (first.rfind(scene.file + ": ", 0) == 0) first.erase(0, scene.file.size() + 2);
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "the " + std::string(toString(sim.solver.type)) +
                             " solver has no joint rows, and the scene has " +
                             std::to_string(scene.joints.size()) + " joints (the first: " + first +
                             "): solve with pgs (it takes particle contacts too: "
                             "--collision particles --solver pgs), or step on opencl, where "
                             "jointed bodies step on the CPU with pgs");
    }
    if (sim.backend != Backend::OpenCl) return {};
    // SAT on the device feeds projected Gauss-Seidel, with every body on the device.
    if (sim.collisionMethod() == CollisionMethod::Sat) {
        if (sim.solver.type == SolverType::Pgs) return {};
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "sat collision on the opencl backend solves with pgs (--solver pgs); "
                         "the " +
                             std::string(toString(sim.solver.type)) +
                             " solver takes particle contacts there (--collision particles)");
    }
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
