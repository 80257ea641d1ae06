// host/tools/solver_suite.cpp: the solver test set run by every solver on every path at equal
// constraint passes (`rubble solvers --suite` prints it, the Python package returns it;
// docs/solvers.md defines the columns).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include <glm/gtc/quaternion.hpp>

#include "rubble/tools.h"

namespace rubble {
namespace {

// A "top" body stands when at the end of the run it is within kStandSideways of where it
// started horizontally and upwards and has sunk less than kStandSink (soft contacts give under
// a load), m.
constexpr double kStandSideways = 0.1;
constexpr double kStandSink = 0.5;

Error bad(const std::string& where, const std::string& message) {
    return makeError(ErrorKind::BadInput, where, message);
}

// Kinetic plus potential energy of the dynamic bodies, J (potential against gravity from the
// origin).
double energy(const World& world, glm::vec3 gravity) {
    double e = 0.0;
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        if (b.isStatic) continue;
        const double m = b.mass;
        e += 0.5 * m * double(glm::dot(b.linearVelocity, b.linearVelocity));
        e += 0.5 * double(glm::dot(b.angularVelocity, b.angularMomentum));
        e -= m * double(glm::dot(gravity, b.position));
    }
    return e;
}

// A joint's anchor in each body's frame, from the scene's world anchor at the initial poses.
struct JointAnchors {
    std::uint32_t a = 0, b = 0;
    glm::vec3 inA{0.0f}, inB{0.0f};
};

std::vector<JointAnchors> jointAnchors(const World& world) {
    std::vector<JointAnchors> out;
    for (const JointDesc& j : world.joints()) {
        const BodyState a = world.body(j.a), b = world.body(j.b);
        out.push_back({j.a, j.b, glm::inverse(a.orientation) * (j.anchor - a.position),
                       glm::inverse(b.orientation) * (j.anchor - b.position)});
    }
    return out;
}

double jointError(const World& world, std::span<const JointAnchors> joints) {
    double worst = 0.0;
    for (const JointAnchors& j : joints) {
        const BodyState a = world.body(j.a), b = world.body(j.b);
        const glm::vec3 pa = a.position + a.orientation * j.inA;
        const glm::vec3 pb = b.position + b.orientation * j.inB;
        worst = std::max(worst, double(glm::length(pb - pa)));
    }
    return worst;
}

// The body the suite watches: the one named "top", else the dynamic body highest at the start.
std::optional<std::uint32_t> watchedBody(const World& world, bool& named) {
    named = false;
    if (std::optional<std::uint32_t> top = world.findBody("top")) {
        named = true;
        return top;
    }
    std::optional<std::uint32_t> highest;
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        if (b.isStatic) continue;
        if (!highest || b.position.y > world.body(*highest).position.y) highest = i;
    }
    return highest;
}

// Appended piece by piece: GCC 12 misreads "x" + std::string(s) as an overlapping copy.
std::string settingsText(SolverType solver, int passes, int relax, int& substeps) {
    std::string text;
    if (solver != SolverType::SoftStep) {
        text.append("iterations=").append(std::to_string(passes));
        return text;
    }
    substeps = std::max(1, passes / (1 + relax));
    text.append("substeps=").append(std::to_string(substeps));
    text.append(" relax=").append(std::to_string(relax));
    return text;
}

// One scene with one solver on one path.
SuiteRow runOne(Scene scene, SolverType solver, const std::string& path, const SuiteOptions& o) {
    SuiteRow row;
    row.scene = scene.name;
    row.solver = std::string(toString(solver));
    row.path = path;
    int substeps = 1;
    row.settings = settingsText(solver, o.passes, o.relax, substeps);
    SimulationOptions& sim = scene.simulation;
    sim.solver.type = solver;
    sim.solver.iterations = o.passes;
    sim.solver.substeps = substeps;
    sim.solver.relaxIterations = o.relax;
    RunOptions run = o.run;
    if (path == "cpu") {
        sim.backend = Backend::Cpu;
        sim.collision.method = CollisionMethod::Sat;
        run.context.reset();
    } else {
        // The device's Gauss-Seidel on SAT contacts: every element colored, or in blocks.
        sim.backend = Backend::OpenCl;
        sim.collision.method = CollisionMethod::Sat;
        run.pgsBlocks = path == "device-colored" ? 0 : -1;
    }
    Result<World> created = World::create(scene, run);
    if (!created) {
        row.skipped = created.error().describe();
        return row;
    }
    World& world = *created;
    const std::vector<JointAnchors> joints = jointAnchors(world);
    bool named = false;
    const std::optional<std::uint32_t> watched = watchedBody(world, named);
    const glm::vec3 start = watched ? world.body(*watched).position : glm::vec3(0.0f);
    glm::vec3 halfway = start;
    const double e0 = energy(world, sim.gravity);
    double wallMs = 0.0;
    for (int step = 0; step < o.steps; ++step) {
        const auto t0 = std::chrono::steady_clock::now();
        const Status s = world.step();
        wallMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                      .count();
        if (!s) {
            row.skipped = s.error().describe();
            break;
        }
        row.steps = step + 1;
        if (watched && row.steps == o.steps / 2) halfway = world.body(*watched).position;
        row.penetration = std::max(row.penetration, double(world.lastStep().largestPenetration));
        row.energyGained = std::max(row.energyGained, energy(world, sim.gravity) - e0);
        row.jointError = std::max(row.jointError, jointError(world, joints));
    }
    if (row.steps > 0) row.msPerStep = wallMs / row.steps;
    if (!watched) return row;
    const glm::vec3 moved = world.body(*watched).position - start;
    row.topDrift = glm::length(moved);
    row.topCreep = glm::length(world.body(*watched).position - halfway);
    const bool stood = row.skipped.empty() && std::hypot(moved.x, moved.z) < kStandSideways &&
                       -moved.y < kStandSink && moved.y < kStandSideways;
    if (named) row.stands = std::string(stood ? "yes" : "no");
    return row;
}

} // namespace

Result<std::vector<SuiteRow>> runSolverSuite(const SuiteOptions& o) {
    if (o.steps < 1) return bad("--steps", "must be 1 or more");
    if (o.passes < 1) return bad("--passes", "must be 1 or more");
    if (o.relax < 0) return bad("--relax", "must be 0 or more");
    for (const std::string& p : o.paths)
        if (p != "cpu" && p != "device-colored" && p != "device-blocks")
            return bad("--paths", "unknown path \"" + p +
                                      "\" (expected cpu, device-colored or device-blocks)");
    std::vector<Scene> scenes;
    for (const std::string& file : o.scenes) {
        Result<Scene> s = loadScene(file);
        RUBBLE_TRY(s);
        scenes.push_back(std::move(*s));
    }
    // One device for every device run, its program built once.
    RunOptions run = o.run;
    std::string noDevice;
    const bool device = std::any_of(o.paths.begin(), o.paths.end(),
                                    [](const std::string& p) { return p != "cpu"; });
    if (device) {
        Result<std::shared_ptr<gpu::Context>> context = openDevice(run);
        if (context)
            run.context = *context;
        else
            noDevice = context.error().describe();
    }
    SuiteOptions withDevice = o;
    withDevice.run = run;
    std::vector<SuiteRow> rows;
    for (const Scene& scene : scenes)
        for (const std::string& path : o.paths)
            for (const SolverType solver : o.solvers) {
                const bool onDevice = path != "cpu";
                // The device's paths are its PGS on SAT contacts; its Jacobi family takes
                // particle contacts, a different contact set, and is not compared here.
                if (onDevice && solver != SolverType::Pgs && solver != SolverType::SoftStep)
                    continue;
                if (onDevice && !noDevice.empty()) {
                    SuiteRow r;
                    r.scene = scene.name;
                    r.solver = std::string(toString(solver));
                    r.path = path;
                    r.skipped = noDevice;
                    rows.push_back(r);
                    continue;
                }
                rows.push_back(runOne(scene, solver, path, withDevice));
            }
    return rows;
}

} // namespace rubble
