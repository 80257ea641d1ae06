// host/app/compare_command.cpp: `rubble compare SCENE --a K=V... --b K=V...`: one scene on two
// configurations, stepped side by side; per step the divergence of the bodies' poses and each
// side's energy, momentum, penetration and solver residual, as a table, a CSV and a plot.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/app/commands.h"
#include "host/app/gpu_commands.h"
#include "rubble/tools.h"
#include "rubble/world.h"

namespace rubble::app {
namespace {

// The interpreter with Debian's python3-matplotlib; `python3` on PATH may be another build.
constexpr const char* kPython = "/usr/bin/python3";

// One side's settings, from its KEY=VALUE list.
struct Side {
    Overrides overrides;
    RunOptions run;
    std::string label; ///< the settings as given, for the table's heading
};

Error badSetting(const char* option, const std::string& item, const std::string& message) {
    return makeError(ErrorKind::BadInput, std::string(option) + " " + item, message);
}

// One KEY=VALUE into the side, read and checked by the option table so that the error names
// the setting; a simulation option is kept as text for applyOverrides.
Status parseSetting(const char* option, const std::string& item, Side& side) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
        return badSetting(option, item, "expected KEY=VALUE");
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    const Option* o = findOptionByName(key);
    if (o == nullptr || !(o->uses & kUseCompare))
        return badSetting(option, item, "unknown key (expected " + compareKeysText() + ")");
    const std::string where = std::string(option) + " " + item;
    if (o->scope == OptionScope::Run)
        return assignOptionText(*o, value, where, OptionTarget{nullptr, &side.run});
    SimulationOptions check; // refuses a bad value now, before the scene is loaded
    RUBBLE_TRY(assignOptionText(*o, value, where, OptionTarget{&check, nullptr}));
    side.overrides.items.push_back({o, where, value});
    return {};
}

// A side's settings: KEY=VALUE items, each possibly a comma-separated list.
Result<Side> parseSide(const char* option, const std::vector<std::string>& items,
                       const RunOptions& base) {
    Side side;
    side.run = base;
    for (const std::string& item : items) {
        std::size_t start = 0;
        while (start <= item.size()) {
            const std::size_t comma = std::min(item.find(',', start), item.size());
            const std::string one = item.substr(start, comma - start);
            if (!one.empty()) {
                RUBBLE_TRY(parseSetting(option, one, side));
                side.label += (side.label.empty() ? "" : " ") + one;
            }
            start = comma + 1;
        }
    }
    if (side.label.empty()) side.label = "(the scene's settings)";
    return side;
}

std::string csvLine(const CompareRow& r) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%lld,%.6f,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,"
                  "%u,%u\n",
                  r.step, r.time, r.positionMax, r.positionRms, r.angleMax, r.angleRms,
                  r.a.kineticEnergy, r.b.kineticEnergy, r.a.linearMomentum, r.b.linearMomentum,
                  r.a.angularMomentum, r.b.angularMomentum, double(r.a.penetration),
                  double(r.b.penetration), double(r.a.residual), double(r.b.residual),
                  r.a.contacts, r.b.contacts);
    return buf;
}

constexpr const char* kCsvHeader =
    "step,time,position_max,position_rms,angle_max,angle_rms,kinetic_energy_a,kinetic_energy_b,"
    "linear_momentum_a,linear_momentum_b,angular_momentum_a,angular_momentum_b,"
    "largest_penetration_a,largest_penetration_b,residual_a,residual_b,contacts_a,contacts_b\n";

void printHeading() {
    std::printf("%6s %8s | %9s %9s %9s %9s | %9s %9s | %9s %9s | %9s %9s | %8s %8s | %8s %8s\n",
                "step", "time", "pos max", "pos rms", "ang max", "ang rms", "KE a", "KE b",
                "|P| a", "|P| b", "|L| a", "|L| b", "pen a", "pen b", "res a", "res b");
    std::printf("%6s %8s | %9s %9s %9s %9s | %9s %9s | %9s %9s | %9s %9s | %8s %8s | %8s %8s\n",
                "", "s", "m", "m", "rad", "rad", "J", "J", "kg m/s", "kg m/s", "kg m2/s",
                "kg m2/s", "m", "m", "N s", "N s");
}

void printRow(const CompareRow& r) {
    std::printf("%6lld %8.4f | %9.2e %9.2e %9.2e %9.2e | %9.3e %9.3e | %9.3e %9.3e | %9.3e "
                "%9.3e | %8.1e %8.1e | %8.1e %8.1e\n",
                r.step, r.time, r.positionMax, r.positionRms, r.angleMax, r.angleRms,
                r.a.kineticEnergy, r.b.kineticEnergy, r.a.linearMomentum, r.b.linearMomentum,
                r.a.angularMomentum, r.b.angularMomentum, double(r.a.penetration),
                double(r.b.penetration), double(r.a.residual), double(r.b.residual));
}

// The plotting script: next to the binary's source tree (build folders live in it), or under
// the working directory.
std::optional<std::string> findPlotScript() {
    std::vector<std::filesystem::path> candidates;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        candidates.push_back(exe.parent_path() / ".." / "bench" / "plot_compare.py");
        candidates.push_back(exe.parent_path() / "bench" / "plot_compare.py");
    }
    candidates.push_back(std::filesystem::current_path(ec) / "bench" / "plot_compare.py");
    for (const std::filesystem::path& p : candidates)
        if (std::filesystem::is_regular_file(p, ec)) return p.lexically_normal().string();
    return std::nullopt;
}

// Runs /usr/bin/python3 on the plotting script; the script says what is missing.
Status drawPlot(const std::string& csv, const std::string& png) {
    if (access(kPython, X_OK) != 0)
        return makeError(ErrorKind::Io, "--plot",
                         std::string(kPython) + " is missing; --plot needs Debian's python3 with "
                         "matplotlib (apt-get install python3-matplotlib). The table is in " + csv);
    const std::optional<std::string> script = findPlotScript();
    if (!script)
        return makeError(ErrorKind::Io, "--plot",
                         "bench/plot_compare.py was not found next to the rubble binary or "
                         "under the working directory. The table is in " + csv);
    std::fflush(stdout);
    const pid_t child = fork();
    if (child < 0) return makeError(ErrorKind::Io, "--plot", "fork failed");
    if (child == 0) {
        execl(kPython, kPython, script->c_str(), csv.c_str(), png.c_str(), (char*)nullptr);
        _exit(127);
    }
    int status = 0;
    if (waitpid(child, &status, 0) < 0) return makeError(ErrorKind::Io, "--plot", "waitpid failed");
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return {};
    if (WIFEXITED(status) && WEXITSTATUS(status) == 3)
        return makeError(ErrorKind::Io, "--plot",
                         "matplotlib is missing for " + std::string(kPython) +
                             " (apt-get install python3-matplotlib). The table is in " + csv);
    return makeError(ErrorKind::Io, "--plot",
                     *script + " failed (exit status " +
                         std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                         "). The table is in " + csv);
}

} // namespace

int compareCommand(const CompareArgs& args) {
    if (args.steps < 1) return report(makeError(ErrorKind::BadInput, "--steps", "must be 1 or more"));
    Result<Side> a = parseSide("--a", args.a, args.run);
    if (!a) return report(a.error());
    Result<Side> b = parseSide("--b", args.b, args.run);
    if (!b) return report(b.error());
    Result<Scene> base = loadScene(args.scene);
    if (!base) return report(base.error());
    Scene sceneA = *base, sceneB = *base;
    if (Status s = applyOverrides(a->overrides, sceneA); !s) return report(s.error());
    if (Status s = applyOverrides(b->overrides, sceneB); !s) return report(s.error());
    Result<Comparison> comparison = Comparison::create(sceneA, a->run, sceneB, b->run);
    if (!comparison) return report(comparison.error());

    std::optional<std::ofstream> csv;
    std::string csvPath = args.csv;
    if (csvPath.empty() && !args.plot.empty())
        csvPath = (std::filesystem::temp_directory_path() /
                   ("rubble_compare_" + std::to_string(getpid()) + ".csv")).string();
    if (!csvPath.empty()) {
        csv.emplace(csvPath, std::ios::binary);
        if (!*csv) return report(makeError(ErrorKind::Io, csvPath, "cannot be written"));
        *csv << kCsvHeader;
    }

    std::printf("%s, %d steps of %.6g s\n  a: %s (%s)\n  b: %s (%s)\n", args.scene.c_str(),
                args.steps, comparison->dt(), a->label.c_str(),
                comparison->a().deviceName().c_str(), b->label.c_str(),
                comparison->b().deviceName().c_str());
    printHeading();
    const int every = std::max(1, args.steps / 10);
    std::optional<Error> failure;
    long long step = 0;
    for (; step <= args.steps; ++step) {
        Result<CompareRow> row = comparison->next();
        if (!row) {
            failure = row.error();
            break;
        }
        if (csv) *csv << csvLine(*row);
        if (step % every == 0 || step == args.steps) printRow(*row);
    }
    if (csv) {
        csv->flush();
        if (!*csv) return report(makeError(ErrorKind::Io, csvPath, "writing failed"));
        csv.reset();
        if (!args.csv.empty()) std::printf("wrote %s\n", args.csv.c_str());
    }
    if (failure) {
        const int code = report(*failure);
        std::fprintf(stderr, "rubble: compare stopped before step %lld%s%s\n", step,
                     args.csv.empty() ? "" : "; the CSV holds the steps before it: ",
                     args.csv.c_str());
        return code;
    }
    if (!args.plot.empty()) {
        const Status drawn = drawPlot(csvPath, args.plot);
        if (args.csv.empty() && drawn) std::filesystem::remove(csvPath);
        if (!drawn) return report(drawn.error());
        std::printf("wrote %s\n", args.plot.c_str());
    }
    return kExitOk;
}

} // namespace rubble::app
