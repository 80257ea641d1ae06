// tests/unit/run_command_test.cpp: `rubble run` writes the documented trajectory and metrics
// files, renamed into place only when complete, and stops cleanly on a non-finite state.
#include <atomic>
#include <sstream>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "host/io/trajectory_writer.h"
#include "support/test_util.h"

namespace rubble {
namespace {

const char* kScene = R"({"format": "rubble-scene", "version": 1, "name": "two balls",
  "simulation": {"dt": 0.01, "steps": 5},
  "shapes": {"ball": {"type": "sphere", "radius": 0.1}},
  "bodies": [{"name": "a", "shape": "ball", "mass": 1, "position": [0, 10, 0]},
             {"name": "b", "shape": "ball", "mass": 1, "position": [1, 10, 0],
              "linear_velocity": [1, 0, 0]}]})";

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// Writes `scene` to dir/s.json and runs `rubble run dir/s.json ARGS`.
test::CommandResult runScene(const std::string& dir, const std::string& scene,
                             const std::string& args) {
    test::writeText(dir + "/s.json", scene);
    return test::runRubble("run " + dir + "/s.json " + args);
}

TEST(RunCommand, WritesCsvEveryKthStep) {
    const std::string dir = test::tempDir("run_csv");
    const test::CommandResult r =
        runScene(dir, kScene, "--out " + dir + "/t.csv --every 2 --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("two balls: 5 steps, 2 bodies"), std::string::npos) << r.output;
    const std::vector<std::string> l = lines(test::readText(dir + "/t.csv"));
    ASSERT_EQ(l.size(), 1u + 2u * 3u); // header, steps 0, 2, 4
    EXPECT_EQ(l[0], "step,time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
    EXPECT_EQ(l[1], "0,0,a,0,10,0,1,0,0,0,0,0,0,0,0,0");
    EXPECT_EQ(l[3].substr(0, 7), "2,0.02,");
    EXPECT_EQ(l[6].substr(0, 9), "4,0.04,b,");
    EXPECT_EQ(test::runShell("ls " + dir + " | grep -c partial").output, "0\n");
}

TEST(RunCommand, WritesJsonLinesWithTheSameFields) {
    const std::string dir = test::tempDir("run_jsonl");
    const test::CommandResult r =
        runScene(dir, kScene, "--out " + dir + "/t.jsonl --steps 3 --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::vector<std::string> l = lines(test::readText(dir + "/t.jsonl"));
    ASSERT_EQ(l.size(), 4u);
    const nlohmann::json last = nlohmann::json::parse(l[3]);
    EXPECT_EQ(last["step"], 3);
    EXPECT_NEAR(last["time"].get<double>(), 0.03, 1e-9);
    ASSERT_EQ(last["bodies"].size(), 2u);
    const nlohmann::json& b = last["bodies"][1];
    EXPECT_EQ(b["body"], "b");
    for (const char* k :
         {"px", "py", "pz", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz"})
        EXPECT_TRUE(b.contains(k)) << k;
    EXPECT_NEAR(b["px"].get<double>(), 1.03, 1e-6);
    EXPECT_NEAR(b["vy"].get<double>(), -3 * 0.01 * 9.81, 1e-5);
}

TEST(RunCommand, WritesMetricsWithTheDocumentedKeys) {
    const std::string dir = test::tempDir("run_metrics");
    const test::CommandResult r = runScene(dir, kScene, "--metrics " + dir + "/m.json --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json m = nlohmann::json::parse(test::readText(dir + "/m.json"));
    for (const char* k :
         {"scene", "steps", "bodies", "wall_s", "ms_per_step", "stages_ms", "kinetic_energy",
          "linear_momentum", "angular_momentum", "largest_penetration", "contact_count",
          "solver_residual", "backend", "device"})
        EXPECT_TRUE(m.contains(k)) << k;
    EXPECT_EQ(m["scene"], "two balls");
    EXPECT_EQ(m["steps"], 5);
    EXPECT_EQ(m["bodies"], 2);
    EXPECT_TRUE(m["ms_per_step"].contains("median"));
    EXPECT_TRUE(m["stages_ms"].contains("broad_phase"));
    EXPECT_EQ(m["backend"], "cpu");
    // Free fall: momentum changes by m g t per body.
    EXPECT_NEAR(m["linear_momentum"]["last"][1].get<double>(), -2 * 9.81 * 0.05, 1e-5);
    EXPECT_NEAR(m["linear_momentum"]["first"][0].get<double>(), 1.0, 1e-9);
}

// The metrics count the bodies asleep after the last step (`asleep.last`), so that benchmark
// runs say how much of a pile their late steps still moved: stack_10 is awake after one second
// and all ten crates sleep by two.
TEST(RunCommand, MetricsCountTheBodiesAsleepAtTheEnd) {
    const std::string dir = test::tempDir("run_asleep");
    for (const auto& [steps, asleep] : {std::pair{60, 0}, {120, 10}}) {
        const test::CommandResult r = test::runRubble(
            "run " + std::string(RUBBLE_SOURCE_DIR) + "/scenes/stack_10.json --steps " +
            std::to_string(steps) + " --metrics " + dir + "/m.json --quiet");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const nlohmann::json m = nlohmann::json::parse(test::readText(dir + "/m.json"));
        EXPECT_EQ(m["asleep"]["last"], asleep) << steps << " steps";
    }
}

TEST(RunCommand, NonFiniteStateStopsCleanlyAndKeepsWhatWasWritten) {
    const std::string dir = test::tempDir("run_nan");
    std::string scene = kScene;
    scene.replace(scene.find("\"linear_velocity\": [1, 0, 0]"), 28,
                  "\"linear_velocity\": [3e38, 0, 0]");
    const test::CommandResult r = runScene(dir, scene, "--out " + dir + "/t.csv --quiet --dt 1");
    EXPECT_EQ(r.exitCode, 3) << r.output;
    EXPECT_NE(r.output.find("body b"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("not finite after step"), std::string::npos) << r.output;
    const std::vector<std::string> l = lines(test::readText(dir + "/t.csv"));
    EXPECT_GE(l.size(), 3u); // the header and step 0 at least
    for (std::size_t i = 1; i < l.size(); ++i)
        EXPECT_EQ(l[i].find("inf"), std::string::npos) << "a non-finite row was written: " << l[i];
}

// The trace is the OpenCL device's commands: asked of the cpu backend, the run is refused before
// it starts, naming the option, and leaves no file.
TEST(RunCommand, TraceWithoutADeviceIsRefused) {
    const std::string dir = test::tempDir("run_trace_cpu");
    const test::CommandResult r = runScene(dir, kScene, "--trace " + dir + "/t.json --quiet");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--trace"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("cpu"), std::string::npos) << r.output;
    EXPECT_EQ(test::runShell("ls " + dir).output, "s.json\n");
}

TEST(RunCommand, VersionAndHelp) {
    test::CommandResult r = test::runRubble("--version");
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_EQ(r.output.rfind("rubble ", 0), 0u) << r.output;
    r = test::runRubble("--help");
    EXPECT_EQ(r.exitCode, 0);
    EXPECT_NE(r.output.find("Examples:"), std::string::npos);
}

// Joint rows live in PGS only: a joint with another solver on the cpu backend would be a free
// pair of bodies, so the run is refused, naming the option, instead of ignoring the joint.
TEST(RunCommand, JointsWithASolverWithoutJointRowsAreRefused) {
    const std::string dir = test::tempDir("run_joints");
    test::writeText(dir + "/s.json", R"({"format": "rubble-scene", "version": 1, "name": "pair",
      "shapes": {"ball": {"type": "sphere", "radius": 0.1}},
      "bodies": [{"name": "a", "shape": "ball", "static": true, "position": [0, 2, 0]},
                 {"name": "b", "shape": "ball", "mass": 1, "position": [0, 1, 0]}],
      "joints": [{"type": "ball", "a": "a", "b": "b", "anchor": [0, 2, 0]}]})");
    for (const char* solver : {"jacobi", "lcp-jacobi", "lemke"}) {
        const test::CommandResult r = test::runRubble(
            "run " + dir + "/s.json --steps 2 --quiet --solver " + std::string(solver));
        EXPECT_EQ(r.exitCode, 2) << solver << ": " << r.output;
        EXPECT_NE(r.output.find("simulation.solver.type: the " + std::string(solver) +
                                " solver has no joint rows"),
                  std::string::npos)
            << r.output;
        EXPECT_NE(r.output.find("(the first: joints[0])"), std::string::npos) << r.output;
    }
    // Particle contacts with PGS keep the joint: the ball hangs 1 m below its anchor (free, it
    // would fall 4.9 m in that second).
    const test::CommandResult ok = test::runRubble(
        "run " + dir + "/s.json --steps 60 --quiet --collision particles --solver pgs --out " +
        dir + "/t.csv");
    ASSERT_EQ(ok.exitCode, 0) << ok.output;
    const std::vector<std::string> last = test::csvRows(test::readText(dir + "/t.csv")).back();
    ASSERT_EQ(last.size(), 16u);
    ASSERT_EQ(last[0] + "," + last[1] + "," + last[2], "60,1,b"); // dt 1/60: one second
    EXPECT_NEAR(std::stod(last[4]), 1.0, 0.005);                  // py
}

// Masses past the promised ratio: the run goes on (exit 0, the trajectory written) and says so
// on stderr, naming the file, both bodies and the ratio; validate says the same.
TEST(RunCommand, WarnsOfMassesPastTheStatedRatioAndRuns) {
    const std::string dir = test::tempDir("run_mass_ratio");
    test::writeText(dir + "/s.json", R"({"format": "rubble-scene", "version": 1,
      "simulation": {"steps": 10},
      "shapes": {"ground": {"type": "plane"}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "light", "shape": "crate", "mass": 1e-9, "position": [0, 0.5, 0]},
                 {"name": "heavy", "shape": "crate", "mass": 1e9, "position": [0, 1.5, 0]}]})");
    const std::string warning = "rubble: warning: " + dir +
                                "/s.json: bodies[1] and bodies[2]: the masses of dynamic bodies "
                                "light (1e-09 kg) and heavy (1e+09 kg) differ 1:1e+18";
    const test::CommandResult run =
        test::runRubble("run " + dir + "/s.json --quiet --out " + dir + "/t.csv");
    EXPECT_EQ(run.exitCode, 0) << run.output;
    EXPECT_NE(run.output.find(warning), std::string::npos) << run.output;
    EXPECT_EQ(lines(test::readText(dir + "/t.csv")).size(), 1u + 3u * 11u);
    const test::CommandResult validate = test::runRubble("validate " + dir + "/s.json");
    EXPECT_EQ(validate.exitCode, 0) << validate.output;
    EXPECT_NE(validate.output.find(warning), std::string::npos) << validate.output;
}

// A scene of many short steps: long enough to be stopped mid-run.
const char* kLongScene = R"({"format": "rubble-scene", "version": 1, "name": "long fall",
  "simulation": {"dt": 0.001, "steps": 100000000, "gravity": [0, 0, 0]},
  "shapes": {"ball": {"type": "sphere", "radius": 0.1}},
  "bodies": [{"name": "a", "shape": "ball", "mass": 1, "linear_velocity": [1, 0, 0]}]})";

// SIGINT and SIGTERM stop the run between steps (or stages): each is said on stderr with the
// partial file's name, the exit status is 128 + the signal, and the partial file holds whole
// rows only. The final name is never written.
TEST(RunCommand, SignalsStopTheRunAndKeepWholeRows) {
    for (const auto& [signal, status, word] :
         {std::tuple{"INT", 130, "interrupted"}, std::tuple{"TERM", 143, "terminated"}}) {
        const std::string dir = test::tempDir(std::string("run_signal_") + signal);
        test::writeText(dir + "/s.json", kLongScene);
        const test::CommandResult r = test::runShell(
            std::string(RUBBLE_BINARY) + " run " + dir + "/s.json --out " + dir +
            "/t.csv --every 1000 --quiet 2>&1 & pid=$!; sleep 1; kill -" + signal +
            " $pid; wait $pid; echo \"status $?\"");
        EXPECT_NE(r.output.find("status " + std::to_string(status)), std::string::npos)
            << r.output;
        EXPECT_NE(r.output.find(std::string("rubble: ") + word + " after step "), std::string::npos)
            << r.output;
        EXPECT_FALSE(std::ifstream(dir + "/t.csv").good());
        const std::string partial = test::runShell("ls " + dir + "/t.csv.*.partial").output;
        ASSERT_NE(partial.find(".partial"), std::string::npos) << partial;
        const std::string text = test::readText(partial.substr(0, partial.find('\n')));
        ASSERT_FALSE(text.empty());
        EXPECT_EQ(text.back(), '\n');
        const auto rows = test::csvRows(text);
        EXPECT_GT(rows.size(), 2u);
        for (const auto& row : rows) ASSERT_EQ(row.size(), 16u);
    }
}

// A stop requested through RunOptions::stop ends World::step between stages.
TEST(RunCommand, StopRequestEndsTheStep) {
    std::atomic<bool> stop{false};
    RunOptions run;
    run.stop = &stop;
    World world = test::worldFromText(kLongScene, run);
    ASSERT_TRUE(world.step().ok());
    stop = true;
    const Status s = world.step();
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().kind, ErrorKind::Interrupted);
    EXPECT_EQ(world.stepIndex(), 1);
}

// Output folders are checked before the first step: the run fails at once and leaves nothing.
TEST(RunCommand, UnwritableOutputsFailBeforeStepping) {
    const std::string dir = test::tempDir("run_outputs");
    test::writeText(dir + "/s.json", kLongScene);
    test::CommandResult r = test::runRubble("run " + dir + "/s.json --quiet --out " + dir +
                                            "/t.csv --metrics " + dir + "/missing/m.json");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("missing/m.json"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("No such file or directory"), std::string::npos) << r.output;
    r = test::runRubble("run " + dir + "/s.json --quiet --out " + dir + "/missing/t.csv");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("missing/t.csv"), std::string::npos) << r.output;
    EXPECT_EQ(test::runShell("ls " + dir).output, "s.json\n");
}

// Two runs writing the same output each have their own temporary file; both finish whole.
TEST(RunCommand, ConcurrentRunsHaveTheirOwnPartialFiles) {
    const std::string dir = test::tempDir("run_twice");
    test::writeText(dir + "/s.json", kScene);
    Result<TrajectoryWriter> a = TrajectoryWriter::open(dir + "/t.csv");
    Result<TrajectoryWriter> b = TrajectoryWriter::open(dir + "/t.csv");
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_NE(a->partialPath(), b->partialPath());
    const TrajectoryRow row{"x", glm::vec3(1.0f), glm::quat(1, 0, 0, 0), glm::vec3(0.0f),
                            glm::vec3(0.0f)};
    ASSERT_TRUE(a->write(0, 0.0, std::span(&row, 1)).ok());
    ASSERT_TRUE(b->write(1, 0.5, std::span(&row, 1)).ok());
    ASSERT_TRUE(a->finish().ok());
    ASSERT_TRUE(b->finish().ok());
    const auto rows = test::csvRows(test::readText(dir + "/t.csv"));
    ASSERT_EQ(rows.size(), 2u); // the header and the row of the last to finish, whole
    EXPECT_EQ(rows[1][0], "1");
    const test::CommandResult r = test::runShell(
        "cd " + dir + " && (" + RUBBLE_BINARY + " run s.json --quiet --out u.csv & " +
        RUBBLE_BINARY + " run s.json --quiet --out u.csv; wait) && ls");
    EXPECT_EQ(r.output.find("partial"), std::string::npos) << r.output;
    EXPECT_EQ(test::csvRows(test::readText(dir + "/u.csv")).size(), 13u) << r.output;
}

// Bodies piled into one point exceed the step's pair budget: exit 4 naming the limit, and the
// steps before it are kept under the final name.
TEST(RunCommand, PairBudgetStopsAPileAtOnePoint) {
    std::string bodies;
    for (int i = 0; i < 600; ++i)
        bodies += std::string(i ? "," : "") + R"({"name": "b)" + std::to_string(i) +
                  R"(", "shape": "box", "mass": 1, "position": [0, 1, 0]})";
    const std::string dir = test::tempDir("run_budget");
    test::writeText(dir + "/s.json", R"({"format": "rubble-scene", "version": 1,
      "shapes": {"box": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [)" + bodies + "]}");
    const test::CommandResult r = test::runRubble("run " + dir + "/s.json --steps 5 --quiet --out " +
                                                  dir + "/t.csv");
    EXPECT_EQ(r.exitCode, 4) << r.output;
    EXPECT_NE(r.output.find("broadPhase: step 1 has more than 103936 broad-phase pairs"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("stopped at step 1"), std::string::npos) << r.output;
    EXPECT_EQ(test::csvRows(test::readText(dir + "/t.csv")).size(), 601u); // header, step 0
}

// Blow-ups end the run with exit status 3 naming the body and the step, never exit 0.
TEST(RunCommand, BlowUpsAreTheRunsFailure) {
    struct Case {
        const char* name;
        const char* scene;
        const char* message;
    };
    const Case cases[] = {
        {"gravity", R"({"format": "rubble-scene", "version": 1,
           "simulation": {"dt": 1, "steps": 50, "gravity": [0, -1e6, 0]},
           "shapes": {"g": {"type": "plane", "normal": [0, 1, 0]},
                      "c": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
           "bodies": [{"name": "floor", "shape": "g", "static": true},
                      {"name": "crate", "shape": "c", "mass": 1, "position": [0, 0.5, 0]}]})",
         "body crate: the simulation blew up in step 2: the bodies' energy"},
        {"spin", R"({"format": "rubble-scene", "version": 1,
           "simulation": {"steps": 120, "gravity": [0, 0, 0]},
           "shapes": {"c": {"type": "box", "half_extents": [1, 0.2, 0.5]}},
           "bodies": [{"name": "spinner", "shape": "c", "mass": 1,
                       "angular_velocity": [1e6, 3e5, 0]}]})",
         "body spinner: the simulation blew up in step 3: the bodies' energy"},
        {"hinge", R"({"format": "rubble-scene", "version": 1, "simulation": {"steps": 120},
           "shapes": {"c": {"type": "box", "half_extents": [0.5, 0.1, 0.1]},
                      "p": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}},
           "bodies": [{"name": "pin", "shape": "p", "static": true, "position": [0, 2, 0]},
                      {"name": "arm", "shape": "c", "mass": 1, "position": [0.6, 2, 0],
                       "angular_velocity": [0, 0, 1e6]}],
           "joints": [{"type": "hinge", "a": "pin", "b": "arm", "anchor": [0, 2, 0],
                       "axis": [0, 0, 1]}]})",
         "body arm: the simulation blew up in step 1: joint 0 came apart"},
    };
    for (const Case& c : cases) {
        const std::string dir = test::tempDir(std::string("run_blowup_") + c.name);
        const test::CommandResult r = runScene(dir, c.scene, "--quiet --out " + dir + "/t.csv");
        EXPECT_EQ(r.exitCode, 3) << c.name << ": " << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.name << ": " << r.output;
        EXPECT_TRUE(std::ifstream(dir + "/t.csv").good()) << c.name;
    }
}

} // namespace
} // namespace rubble
