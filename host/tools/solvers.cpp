// host/tools/solvers.cpp: one step's contact set frozen, and every solver's residual and
// complementarity error on it, iteration by iteration (`rubble solvers` prints it, the Python
// package returns it; docs/solvers.md defines the numbers).
#include <span>

#include "host/core/step_params.h"
#include "host/gpu/context.h"
#include "host/world/frozen_contacts.h"
#include "rubble/tools.h"

namespace rubble {
namespace {

SolverIterate publicIterate(const IterateErrors& e) {
    return SolverIterate{e.residual, e.complementarity, e.velocityError};
}

SolverHistory measured(std::string solver, std::string backend, const Result<Iterates>& iterates,
                       const DenseLcp& p, std::span<const double> referenceW) {
    SolverHistory h{std::move(solver), std::move(backend), {}, {}};
    if (!iterates) {
        h.skipped = iterates.error().describe();
        return h;
    }
    for (const std::vector<float>& lambda : *iterates)
        h.iterates.push_back(publicIterate(measureIterate(p, lambda, referenceW)));
    return h;
}

} // namespace

Result<SolversTable> compareSolvers(Scene scene, const RunOptions& run, int step, int iterations,
                                    bool frictionless) {
    if (iterations < 1)
        return makeError(ErrorKind::BadInput, "--iterations", "must be 1 or more");
    // The reference pipeline finds the contacts: cpu backend, pgs.
    scene.simulation.backend = Backend::Cpu;
    scene.simulation.solver.type = SolverType::Pgs;
    if (frictionless)
        for (MaterialDesc& m : scene.materials) m.friction = 0.0f;
    RunOptions cpuRun = run;
    cpuRun.device.clear();
    Result<World> world = World::create(scene, cpuRun);
    RUBBLE_TRY(world);
    Result<FrozenContacts> set = freezeContacts(*world, step);
    RUBBLE_TRY(set);
    if (set->contacts.empty())
        return makeError(ErrorKind::BadInput, "--step",
                         "step " + std::to_string(step) + " of " + scene.file +
                             " has no contacts; choose a later step");
    Result<FrozenProblem> problem = freezeProblem(*set);
    RUBBLE_TRY(problem);
    const FrozenProblem& p = *problem;
    const DenseLcp& dense = p.dense;
    const SolverOptions& opts = p.set.solver;

    SolversTable table;
    table.collision = std::string(toString(scene.simulation.collisionMethod()));
    table.contacts = dense.contacts;
    table.rows = dense.size();
    table.frictionless = dense.stride == 1;

    // Lemke's answer first: its w is the reference of the velocity error.
    std::vector<double> lemkeW;
    if (Result<LemkeSolution> l = lemkeOf(p); l) {
        table.lemkePivots = l->pivots;
        table.lemke = publicIterate(measureIterate(dense, std::span<const double>(l->z)));
        lemkeW = std::move(l->w);
    } else {
        table.lemkeSkipped = l.error().message;
    }
    const std::span<const double> reference =
        table.lemkePivots ? std::span<const double>(lemkeW) : std::span<const double>();

    const int k = iterations;
    std::vector<SolverHistory>& h = table.histories;
    h.push_back(measured("pgs", "cpu", pgsIterates(p, k, opts.relaxation), dense, reference));
    h.push_back(
        measured("jacobi", "cpu", jacobiIterates(p, k, jacobiRelaxation(opts)), dense, reference));
    Result<std::shared_ptr<gpu::Context>> context = gpu::Context::create(run);
    if (context) {
        h.push_back(measured("jacobi", "opencl",
                             jacobiIteratesOnDevice(*context, p, k, jacobiRelaxation(opts)),
                             dense, reference));
    } else {
        h.push_back(SolverHistory{"jacobi", "opencl", {}, context.error().describe()});
    }
    h.push_back(measured("lcp-jacobi", "cpu", lcpJacobiIterates(p, k, lcpJacobiRelaxation(opts)),
                         dense, reference));
    if (context) {
        h.push_back(measured(
            "lcp-jacobi", "opencl",
            lcpJacobiIteratesOnDevice(**context, dense, k, lcpJacobiRelaxation(opts)), dense,
            reference));
    } else {
        h.push_back(SolverHistory{"lcp-jacobi", "opencl", {}, context.error().describe()});
    }
    return table;
}

} // namespace rubble
