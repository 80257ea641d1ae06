// host/world/backend_check.cpp: the combinations of backend, collision method and solver.
#include "host/world/backend_check.h"

#include <string>

#include "host/world/offload.h"

namespace rubble {

Status checkBackendCombination(const Scene& scene) {
    const SimulationOptions& sim = scene.simulation;
    const std::string field = scene.file + ": simulation.";
    const SolverType solver = sim.solverType();
    // The device's soft step goes through the SAT path's pairs, plan and rows; particle
    // contacts have none of them: refused rather than replaced by another solver.
    if (sim.backend == Backend::OpenCl && solver == SolverType::SoftStep &&
        sim.collisionMethod() != CollisionMethod::Sat)
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "the soft-step solver on the opencl backend takes sat contacts only "
                         "(simulation.collision.method: \"sat\", --collision sat); particle "
                         "contacts solve with pgs or the jacobi family (--solver pgs)");
    // Joint rows live in PGS and the soft step; the other solvers take contact rows only. On the
    // cpu backend, and on opencl with SAT, every body steps with the scene's solver, so a joint
    // needs pgs (on opencl with particles jointed bodies step on the CPU with PGS).
    const bool deviceSat =
        sim.backend == Backend::OpenCl && sim.collisionMethod() == CollisionMethod::Sat;
    const bool jointRows = solver == SolverType::Pgs || solver == SolverType::SoftStep;
    if ((sim.backend != Backend::OpenCl || deviceSat) && !jointRows && !scene.joints.empty()) {
        std::string first = scene.joints.front().where;
        if (first.rfind(scene.file + ": ", 0) == 0) first.erase(0, scene.file.size() + 2);
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "the " + std::string(toString(solver)) +
                             " solver has no joint rows, and the scene has " +
                             std::to_string(scene.joints.size()) + " joints (the first: " + first +
                             "): solve with pgs (it takes particle contacts too: "
                             "--collision particles --solver pgs), or step on opencl with "
                             "particles, where jointed bodies step on the CPU with pgs");
    }
    if (sim.backend != Backend::OpenCl) return {};
    // SAT on the device feeds projected Gauss-Seidel or the soft step, with every body on the
    // device.
    if (deviceSat) {
        if (solver == SolverType::Pgs || solver == SolverType::SoftStep) return {};
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "sat collision on the opencl backend solves with pgs or soft-step "
                         "(--solver pgs); the " +
                             std::string(toString(solver)) +
                             " solver takes particle contacts there (--collision particles)");
    }
    // Particle contacts on the device feed PGS or the Jacobi family. With a debris set, pgs is
    // the CPU bodies' solver and the set takes jacobi (deviceSolver).
    const SolverType device = deviceSolver(scene);
    if (device == SolverType::Pgs && !scene.joints.empty() && sim.coupling == Coupling::TwoWay)
        return makeError(ErrorKind::NotSupported, field + "coupling",
                         "two-way coupling gathers the device's impulses on the CPU's bodies "
                         "(here the jointed ones) from the Jacobi rows, and the device solves "
                         "these particle contacts with pgs: couple one way, solve the particles "
                         "with jacobi (--solver jacobi), or collide with sat (--collision sat "
                         "puts every body, jointed ones too, on the device)");
    if (device == SolverType::Lemke)
        return makeError(ErrorKind::NotSupported, field + "solver.type",
                         "the lemke solver does not take particle contacts on the opencl "
                         "backend: solve them with jacobi or lcp-jacobi (--solver jacobi), or "
                         "step with pgs on sat contacts (--collision sat --solver pgs), which "
                         "puts every body, jointed ones too, on the device");
    // Jointed bodies stay on the CPU; a joint on a debris body cannot.
    const std::vector<std::uint8_t> onDevice = deviceBodies(scene);
    for (const JointDesc& j : scene.joints) {
        const std::uint32_t d = onDevice[j.a] ? j.a : j.b;
        if (!onDevice[d]) continue;
        return makeError(ErrorKind::NotSupported, j.where,
                         "joins debris body \"" + scene.bodies[d].name +
                             "\": the debris set steps on the OpenCL device, which has no joint "
                             "rows (leave the body out of the debris set, or collide with sat: "
                             "--collision sat puts every body, jointed ones too, on the device)");
    }
    return {};
}

} // namespace rubble
