// host/app/solvers_command.cpp: `rubble solvers SCENE --step N`: one step's contact set frozen,
// and every solver's residual and complementarity error on it, iteration by iteration, as a
// table and a CSV (docs/solvers.md defines the numbers).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "host/app/commands.h"
#include "host/app/gpu_commands.h"
#include "host/core/step_params.h"
#include "host/gpu/context.h"
#include "host/world/frozen_contacts.h"

namespace rubble::app {
namespace {

// One solver on one backend: its errors after each iteration, or why it did not run.
struct History {
    std::string solver, backend;
    std::vector<IterateErrors> errors;
    std::string skipped;
};

History measured(std::string solver, std::string backend, const Result<Iterates>& iterates,
                 const DenseLcp& p, std::span<const double> referenceW) {
    History h{std::move(solver), std::move(backend), {}, {}};
    if (!iterates) {
        h.skipped = iterates.error().describe();
        return h;
    }
    for (const std::vector<float>& lambda : *iterates)
        h.errors.push_back(measureIterate(p, lambda, referenceW));
    return h;
}

// The iterations the table shows: 1, 2, 5, 10, 20, 50, ... up to the last, and the last.
std::vector<int> checkpoints(int last) {
    std::vector<int> out;
    for (int decade = 1; decade <= last; decade *= 10)
        for (int m : {1, 2, 5})
            if (m * decade < last) out.push_back(m * decade);
    out.push_back(last);
    while (out.size() > 7) out.erase(out.begin());
    return out;
}

std::string optionalNumber(const std::optional<double>& v) {
    if (!v) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6e", *v);
    return buf;
}

Status writeCsv(const std::string& path, const std::vector<History>& histories,
                const std::optional<LemkeSolution>& lemke, const IterateErrors& lemkeErrors) {
    std::ofstream out(path, std::ios::binary);
    if (!out) return makeError(ErrorKind::Io, path, "cannot be written");
    // One row per solver, backend and iteration; lemke's `iteration` is its pivot count.
    out << "solver,backend,iteration,residual,complementarity,velocity_error\n";
    char buf[160];
    for (const History& h : histories)
        for (std::size_t k = 0; k < h.errors.size(); ++k) {
            const IterateErrors& e = h.errors[k];
            std::snprintf(buf, sizeof buf, "%s,%s,%zu,%.6e,%.6e,", h.solver.c_str(),
                          h.backend.c_str(), k + 1, e.residual, e.complementarity);
            out << buf << optionalNumber(e.velocityError) << "\n";
        }
    if (lemke) {
        std::snprintf(buf, sizeof buf, "lemke,cpu,%d,%.6e,%.6e,0\n", lemke->pivots,
                      lemkeErrors.residual, lemkeErrors.complementarity);
        out << buf;
    }
    out.flush();
    if (!out) return makeError(ErrorKind::Io, path, "writing failed");
    return {};
}

void printTable(const std::vector<History>& histories, int iterations,
                const std::optional<LemkeSolution>& lemke, const IterateErrors& lemkeErrors,
                const std::string& lemkeSkipped) {
    const std::vector<int> shown = checkpoints(iterations);
    std::printf("residual (m/s) after k iterations; complementarity (N m) and velocity error "
                "against lemke (m/s) after the last\n");
    std::printf("%-11s %-7s", "solver", "backend");
    for (int k : shown) std::printf(" %9s", ("k=" + std::to_string(k)).c_str());
    std::printf(" %11s %11s\n", "compl.", "vel. error");
    for (const History& h : histories) {
        std::printf("%-11s %-7s", h.solver.c_str(), h.backend.c_str());
        if (!h.skipped.empty()) {
            std::printf(" skipped: %s\n", h.skipped.c_str());
            continue;
        }
        for (int k : shown) std::printf(" %9.2e", h.errors[std::size_t(k - 1)].residual);
        const IterateErrors& last = h.errors.back();
        std::printf(" %11.2e", last.complementarity);
        if (last.velocityError) std::printf(" %11.2e\n", *last.velocityError);
        else std::printf(" %11s\n", "-");
    }
    if (lemke)
        std::printf("%-11s %-7s exact after %d pivots: residual %.2e, complementarity %.2e\n",
                    "lemke", "cpu", lemke->pivots, lemkeErrors.residual,
                    lemkeErrors.complementarity);
    else
        std::printf("%-11s %-7s skipped: %s\n", "lemke", "cpu", lemkeSkipped.c_str());
}

} // namespace

int solversCommand(const SolversArgs& args) {
    if (args.iterations < 1)
        return report(makeError(ErrorKind::BadInput, "--iterations", "must be 1 or more"));
    Result<Scene> scene = loadScene(args.scene);
    if (!scene) return report(scene.error());
    // The reference pipeline finds the contacts: cpu backend, pgs.
    if (Status s = applyOverrides(args.overrides, *scene); !s) return report(s.error());
    scene->simulation.backend = Backend::Cpu;
    scene->simulation.solver.type = SolverType::Pgs;
    if (args.frictionless)
        for (MaterialDesc& m : scene->materials) m.friction = 0.0f;
    RunOptions cpuRun = args.run;
    cpuRun.device.clear();
    Result<World> world = World::create(*scene, cpuRun);
    if (!world) return report(world.error());
    Result<FrozenContacts> set = freezeContacts(*world, args.step);
    if (!set) return report(set.error());
    if (set->contacts.empty())
        return report(makeError(ErrorKind::BadInput, "--step",
                                "step " + std::to_string(args.step) + " of " + args.scene +
                                    " has no contacts; choose a later step"));
    Result<FrozenProblem> problem = freezeProblem(*set);
    if (!problem) return report(problem.error());
    const FrozenProblem& p = *problem;
    const DenseLcp& dense = p.dense;
    const SolverOptions& opts = p.set.solver;

    std::printf("%s, step %d (%s collision): %u contacts, %u dense rows (%s); every solver "
                "starts from zero impulses\n",
                args.scene.c_str(), args.step,
                std::string(toString(scene->simulation.collisionMethod())).c_str(),
                dense.contacts, dense.size(),
                dense.stride == 1 ? "frictionless: normal rows only"
                                  : "normal and two friction rows per contact");

    // Lemke's answer first: its w is the reference of the velocity error.
    std::optional<LemkeSolution> lemke;
    std::string lemkeSkipped;
    IterateErrors lemkeErrors;
    if (Result<LemkeSolution> l = lemkeOf(p); l) {
        lemke = std::move(*l);
        lemkeErrors = measureIterate(dense, std::span<const double>(lemke->z));
    } else {
        lemkeSkipped = l.error().message;
    }
    const std::span<const double> reference =
        lemke ? std::span<const double>(lemke->w) : std::span<const double>();

    const int k = args.iterations;
    std::vector<History> histories;
    histories.push_back(
        measured("pgs", "cpu", pgsIterates(p, k, opts.relaxation), dense, reference));
    histories.push_back(
        measured("jacobi", "cpu", jacobiIterates(p, k, jacobiRelaxation(opts)), dense, reference));
    Result<std::shared_ptr<gpu::Context>> context = gpu::Context::create(args.run);
    if (context) {
        histories.push_back(measured("jacobi", "opencl",
                                     jacobiIteratesOnDevice(*context, p, k,
                                                            jacobiRelaxation(opts)),
                                     dense, reference));
    } else {
        histories.push_back(History{"jacobi", "opencl", {}, context.error().describe()});
    }
    histories.push_back(measured("lcp-jacobi", "cpu",
                                 lcpJacobiIterates(p, k, lcpJacobiRelaxation(opts)), dense,
                                 reference));
    if (context) {
        histories.push_back(measured("lcp-jacobi", "opencl",
                                     lcpJacobiIteratesOnDevice(**context, dense, k,
                                                               lcpJacobiRelaxation(opts)),
                                     dense, reference));
    } else {
        histories.push_back(History{"lcp-jacobi", "opencl", {}, context.error().describe()});
    }

    printTable(histories, k, lemke, lemkeErrors, lemkeSkipped);
    if (!args.csv.empty()) {
        if (Status s = writeCsv(args.csv, histories, lemke, lemkeErrors); !s)
            return report(s.error());
        std::printf("wrote %s\n", args.csv.c_str());
    }
    return kExitOk;
}

} // namespace rubble::app
