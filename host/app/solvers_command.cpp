// host/app/solvers_command.cpp: `rubble solvers SCENE --step N`: one step's contact set frozen,
// and every solver's residual and complementarity error on it, iteration by iteration, as a
// table and a CSV (docs/solvers.md defines the numbers).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include "host/app/commands.h"
#include "host/app/gpu_commands.h"
#include "rubble/tools.h"

namespace rubble::app {
namespace {

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

Status writeCsv(const std::string& path, const SolversTable& table) {
    std::ofstream out(path, std::ios::binary);
    if (!out) return makeError(ErrorKind::Io, path, "cannot be written");
    // One row per solver, backend and iteration; lemke's `iteration` is its pivot count.
    out << "solver,backend,iteration,residual,complementarity,velocity_error\n";
    char buf[160];
    for (const SolverHistory& h : table.histories)
        for (std::size_t k = 0; k < h.iterates.size(); ++k) {
            const SolverIterate& e = h.iterates[k];
            std::snprintf(buf, sizeof buf, "%s,%s,%zu,%.6e,%.6e,", h.solver.c_str(),
                          h.backend.c_str(), k + 1, e.residual, e.complementarity);
            out << buf << optionalNumber(e.velocityError) << "\n";
        }
    if (table.lemkePivots) {
        std::snprintf(buf, sizeof buf, "lemke,cpu,%d,%.6e,%.6e,0\n", *table.lemkePivots,
                      table.lemke.residual, table.lemke.complementarity);
        out << buf;
    }
    out.flush();
    if (!out) return makeError(ErrorKind::Io, path, "writing failed");
    return {};
}

void printTable(const SolversTable& table, int iterations) {
    const std::vector<int> shown = checkpoints(iterations);
    std::printf("residual (m/s) after k iterations; complementarity (N m) and velocity error "
                "against lemke (m/s) after the last\n");
    std::printf("%-11s %-7s", "solver", "backend");
    for (int k : shown) std::printf(" %9s", ("k=" + std::to_string(k)).c_str());
    std::printf(" %11s %11s\n", "compl.", "vel. error");
    for (const SolverHistory& h : table.histories) {
        std::printf("%-11s %-7s", h.solver.c_str(), h.backend.c_str());
        if (!h.skipped.empty()) {
            std::printf(" skipped: %s\n", h.skipped.c_str());
            continue;
        }
        for (int k : shown) std::printf(" %9.2e", h.iterates[std::size_t(k - 1)].residual);
        const SolverIterate& last = h.iterates.back();
        std::printf(" %11.2e", last.complementarity);
        if (last.velocityError) std::printf(" %11.2e\n", *last.velocityError);
        else std::printf(" %11s\n", "-");
    }
    if (table.lemkePivots)
        std::printf("%-11s %-7s exact after %d pivots: residual %.2e, complementarity %.2e\n",
                    "lemke", "cpu", *table.lemkePivots, table.lemke.residual,
                    table.lemke.complementarity);
    else
        std::printf("%-11s %-7s skipped: %s\n", "lemke", "cpu", table.lemkeSkipped.c_str());
}

} // namespace

std::string suiteNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// The suite's rows as CSV: the columns of SuiteRow, a skipped run's reason quoted.
Status writeSuiteCsv(const std::string& path, std::span<const SuiteRow> rows) {
    std::ofstream out(path, std::ios::binary);
    if (!out) return makeError(ErrorKind::Io, path, "cannot be written");
    out << "scene,solver,path,settings,steps,stands,top_drift,top_creep,penetration,"
           "energy_gained,joint_error,ms_per_step,skipped\n";
    for (const SuiteRow& r : rows) {
        std::string why = r.skipped;
        std::replace(why.begin(), why.end(), '"', '\'');
        std::replace(why.begin(), why.end(), '\n', ' ');
        out << r.scene << ',' << r.solver << ',' << r.path << ',' << r.settings << ','
            << r.steps << ',' << r.stands << ',' << suiteNumber(r.topDrift) << ','
            << suiteNumber(r.topCreep) << ',' << suiteNumber(r.penetration) << ',' << suiteNumber(r.energyGained) << ','
            << suiteNumber(r.jointError) << ',' << suiteNumber(r.msPerStep) << ",\"" << why
            << "\"\n";
    }
    out.flush();
    if (!out) return makeError(ErrorKind::Io, path, "writing failed");
    return {};
}

// The scene files of the suite: the folder's *.json in name order, or the one file.
std::vector<std::string> suiteScenes(const std::string& where) {
    namespace fs = std::filesystem;
    std::vector<std::string> files;
    std::error_code ec;
    if (!fs::is_directory(where, ec)) return {where};
    for (const fs::directory_entry& e : fs::directory_iterator(where, ec))
        if (e.path().extension() == ".json") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    return files;
}

int suiteCommand(const SolversArgs& args) {
    SuiteOptions o;
    o.scenes = suiteScenes(args.scene);
    if (o.scenes.empty())
        return report(makeError(ErrorKind::BadInput, args.scene, "has no *.json scenes"));
    o.steps = args.steps;
    o.passes = args.passes;
    o.relax = args.relax;
    o.paths = args.paths;
    o.run = args.run;
    Result<std::vector<SuiteRow>> rows = runSolverSuite(o);
    if (!rows) return report(rows.error());
    std::printf("| scene | solver | path | settings | stands | top drift (m) | top creep (m) | "
                "deepest penetration (m) | energy gained (J) | joint error (m) | ms/step |\n"
                "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for (const SuiteRow& r : *rows) {
        if (!r.skipped.empty() && r.steps == 0) {
            std::printf("| %s | %s | %s | %s | skipped: %s | | | | | | |\n", r.scene.c_str(),
                        r.solver.c_str(), r.path.c_str(), r.settings.c_str(),
                        r.skipped.c_str());
            continue;
        }
        std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.scene.c_str(),
                    r.solver.c_str(), r.path.c_str(), r.settings.c_str(),
                    (r.skipped.empty() ? r.stands : "stopped at step " +
                                                         std::to_string(r.steps))
                        .c_str(),
                    suiteNumber(r.topDrift).c_str(), suiteNumber(r.topCreep).c_str(),
                    suiteNumber(r.penetration).c_str(),
                    suiteNumber(r.energyGained).c_str(), suiteNumber(r.jointError).c_str(),
                    suiteNumber(r.msPerStep).c_str());
    }
    if (!args.csv.empty()) {
        if (Status s = writeSuiteCsv(args.csv, *rows); !s) return report(s.error());
        std::printf("wrote %s\n", args.csv.c_str());
    }
    return kExitOk;
}

int solversCommand(const SolversArgs& args) {
    if (args.suite) return suiteCommand(args);
    if (args.iterations < 1)
        return report(makeError(ErrorKind::BadInput, "--iterations", "must be 1 or more"));
    Result<Scene> scene = loadScene(args.scene);
    if (!scene) return report(scene.error());
    // --collision picks the method that finds the contacts; the rest is the library's.
    if (Status s = applyOverrides(args.overrides, *scene); !s) return report(s.error());
    Result<SolversTable> table =
        compareSolvers(*scene, args.run, args.step, args.iterations, args.frictionless);
    if (!table) return report(table.error());

    std::printf("%s, step %d (%s collision): %u contacts, %u dense rows (%s); every solver "
                "starts from zero impulses\n",
                args.scene.c_str(), args.step, table->collision.c_str(), table->contacts,
                table->rows,
                table->frictionless ? "frictionless: normal rows only"
                                    : "normal and two friction rows per contact");
    printTable(*table, args.iterations);
    if (!args.csv.empty()) {
        if (Status s = writeCsv(args.csv, *table); !s) return report(s.error());
        std::printf("wrote %s\n", args.csv.c_str());
    }
    return kExitOk;
}

} // namespace rubble::app
