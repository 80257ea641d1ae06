// host/app/compare_command.cpp: `rubble compare SCENE --a K=V... --b K=V...`: one scene on two
// configurations, stepped side by side; per step the divergence of the bodies' poses and each
// side's energy, momentum, penetration and solver residual, as a table, a CSV and a plot.
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/app/commands.h"
#include "host/app/gpu_commands.h"
#include "host/world/world_state.h"

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

template <class T> bool parseNumber(const std::string& text, T& out) {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, out);
    return ec == std::errc() && ptr == end;
}

// One KEY=VALUE into the side; the value is checked here so that the error names the setting.
Status parseSetting(const char* option, const std::string& item, Side& side) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
        return badSetting(option, item, "expected KEY=VALUE");
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    Overrides& o = side.overrides;
    if (key == "backend") {
        if (!parseBackend(value)) return badSetting(option, item, "expected cpu or opencl");
        o.backend = value;
    } else if (key == "collision") {
        if (!parseCollisionMethod(value))
            return badSetting(option, item, "expected sat or particles");
        o.collision = value;
    } else if (key == "solver") {
        if (!parseSolverType(value))
            return badSetting(option, item, "expected pgs, jacobi, lcp-jacobi or lemke");
        o.solver = value;
    } else if (key == "integrator") {
        if (!parseIntegrator(value))
            return badSetting(option, item, "expected symplectic or explicit");
        o.integrator = value;
    } else if (key == "iterations") {
        int n = 0;
        if (!parseNumber(value, n) || n < 1)
            return badSetting(option, item, "expected a whole number of 1 or more");
        o.iterations = n;
    } else if (key == "particle-spacing" || key == "particle_spacing") {
        float v = 0;
        if (!parseNumber(value, v) || !(v >= float(kMinLength) && v <= float(kMaxLength)))
            return badSetting(option, item, "expected a length from 0.0001 to 100000 m");
        o.particleSpacing = v;
    } else if (key == "dt") {
        float v = 0;
        if (!parseNumber(value, v) || !std::isnormal(v) || !(v > 0.0f))
            return badSetting(option, item, "expected a time step in s greater than 0");
        o.dt = v;
    } else if (key == "device") {
        side.run.device = value;
    } else if (key == "deterministic") {
        if (value == "true" || value == "1" || value == "yes") side.run.deterministic = true;
        else if (value == "false" || value == "0" || value == "no") side.run.deterministic = false;
        else return badSetting(option, item, "expected true or false");
    } else {
        return badSetting(option, item,
                          "unknown key (expected backend, collision, solver, iterations, "
                          "integrator, particle-spacing, dt, device or deterministic)");
    }
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

// What one side is at one compared step.
struct SideSample {
    double kineticEnergy = 0;   ///< J
    double linearMomentum = 0;  ///< |sum P|, kg m/s
    double angularMomentum = 0; ///< |sum x x P + L| about the origin, kg m^2/s
    float penetration = 0;      ///< m, largest over the step's substeps
    float residual = 0;         ///< the last substep's solver residual, N s
    std::uint32_t contacts = 0;
};

SideSample sample(const World& w, const std::vector<BodyState>& bodies) {
    SideSample s;
    glm::dvec3 p(0.0), l(0.0);
    for (const BodyState& b : bodies) {
        if (b.isStatic) continue;
        const glm::dvec3 v(b.linearVelocity), omega(b.angularVelocity);
        const glm::dvec3 pl(b.linearMomentum), pa(b.angularMomentum);
        s.kineticEnergy += 0.5 * double(b.mass) * glm::dot(v, v) + 0.5 * glm::dot(omega, pa);
        p += pl;
        l += glm::cross(glm::dvec3(b.position), pl) + pa;
    }
    s.linearMomentum = glm::length(p);
    s.angularMomentum = glm::length(l);
    s.residual = w.lastStep().solverResidual;
    s.contacts = w.lastStep().contactCount;
    return s;
}

std::vector<BodyState> bodiesOf(const World& w) {
    std::vector<BodyState> out(w.bodyCount());
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) out[i] = w.body(i);
    return out;
}

// Divergence of the dynamic bodies: position distance and rotation angle, max and RMS.
struct Divergence {
    double positionMax = 0, positionRms = 0, angleMax = 0, angleRms = 0;
};

Divergence divergence(const std::vector<BodyState>& a, const std::vector<BodyState>& b) {
    Divergence d;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].isStatic) continue;
        const double dx = glm::length(glm::dvec3(a[i].position) - glm::dvec3(b[i].position));
        // The angle of conj(qa) qb (unit quaternions), from its vector part: accurate for small
        // angles, and exactly 0 for equal orientations.
        const glm::dquat r = glm::conjugate(glm::dquat(a[i].orientation)) * glm::dquat(b[i].orientation);
        const double angle = 2.0 * std::atan2(glm::length(glm::dvec3(r.x, r.y, r.z)), std::abs(r.w));
        d.positionMax = std::max(d.positionMax, dx);
        d.angleMax = std::max(d.angleMax, angle);
        d.positionRms += dx * dx;
        d.angleRms += angle * angle;
        ++n;
    }
    if (n > 0) {
        d.positionRms = std::sqrt(d.positionRms / double(n));
        d.angleRms = std::sqrt(d.angleRms / double(n));
    }
    return d;
}

struct Row {
    long long step = 0;
    double time = 0;
    Divergence d;
    SideSample a, b;
};

std::string csvLine(const Row& r) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%lld,%.6f,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,"
                  "%u,%u\n",
                  r.step, r.time, r.d.positionMax, r.d.positionRms, r.d.angleMax, r.d.angleRms,
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

void printRow(const Row& r) {
    std::printf("%6lld %8.4f | %9.2e %9.2e %9.2e %9.2e | %9.3e %9.3e | %9.3e %9.3e | %9.3e "
                "%9.3e | %8.1e %8.1e | %8.1e %8.1e\n",
                r.step, r.time, r.d.positionMax, r.d.positionRms, r.d.angleMax, r.d.angleRms,
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

// Whole steps of each side per compared step: the larger dt sets the pace, and must be a
// whole multiple of the smaller.
Result<std::pair<int, int>> stepRatio(float dtA, float dtB) {
    const double big = std::max(dtA, dtB), small = std::min(dtA, dtB);
    const double ratio = big / small;
    const long whole = std::lround(ratio);
    if (std::abs(ratio - double(whole)) > 1e-4 * ratio)
        return makeError(ErrorKind::BadInput, "--a dt / --b dt",
                         "the two time steps (" + std::to_string(dtA) + " s and " +
                             std::to_string(dtB) + " s) must be equal or one a whole multiple "
                             "of the other");
    return dtA >= dtB ? std::pair<int, int>{1, int(whole)} : std::pair<int, int>{int(whole), 1};
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
    Result<std::pair<int, int>> ratio = stepRatio(sceneA.simulation.dt, sceneB.simulation.dt);
    if (!ratio) return report(ratio.error());
    Result<World> worldA = World::create(sceneA, a->run);
    if (!worldA) return report(worldA.error());
    Result<World> worldB = World::create(sceneB, b->run);
    if (!worldB) return report(worldB.error());

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

    const double dt = std::max(sceneA.simulation.dt, sceneB.simulation.dt);
    std::printf("%s, %d steps of %.6g s\n  a: %s (%s)\n  b: %s (%s)\n", args.scene.c_str(),
                args.steps, dt, a->label.c_str(), worldA->deviceName().c_str(), b->label.c_str(),
                worldB->deviceName().c_str());
    printHeading();
    const int every = std::max(1, args.steps / 10);
    std::optional<Error> failure;
    Row row;
    for (int step = 0; step <= args.steps; ++step) {
        row = Row{};
        row.step = step;
        row.time = double(step) * dt;
        // Both sides advance to the same time; step 0 is the scene as loaded.
        for (auto [w, substeps, out] : {std::tuple{&*worldA, ratio->first, &row.a},
                                        std::tuple{&*worldB, ratio->second, &row.b}}) {
            if (step == 0 || failure) continue;
            float penetration = 0.0f;
            for (int i = 0; i < substeps && !failure; ++i) {
                if (Status s = w->step(); !s) failure = s.error();
                penetration = std::max(penetration, w->lastStep().largestPenetration);
            }
            out->penetration = penetration;
        }
        if (failure) break;
        const std::vector<BodyState> bodiesA = bodiesOf(*worldA), bodiesB = bodiesOf(*worldB);
        const float penA = row.a.penetration, penB = row.b.penetration;
        row.a = sample(*worldA, bodiesA);
        row.b = sample(*worldB, bodiesB);
        row.a.penetration = penA;
        row.b.penetration = penB;
        row.d = divergence(bodiesA, bodiesB);
        if (csv) *csv << csvLine(row);
        if (step % every == 0 || step == args.steps) printRow(row);
    }
    if (csv) {
        csv->flush();
        if (!*csv) return report(makeError(ErrorKind::Io, csvPath, "writing failed"));
        csv.reset();
        if (!args.csv.empty()) std::printf("wrote %s\n", args.csv.c_str());
    }
    if (failure) {
        const int code = report(*failure);
        std::fprintf(stderr, "rubble: compare stopped before step %lld%s%s\n", row.step,
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
