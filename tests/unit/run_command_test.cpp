// tests/unit/run_command_test.cpp: `rubble run` writes the documented trajectory and metrics
// files, renamed into place only when complete, and stops cleanly on a non-finite state.
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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

TEST(RunCommand, WritesCsvEveryKthStep) {
    const std::string dir = test::tempDir("run_csv");
    test::writeText(dir + "/s.json", kScene);
    const test::CommandResult r =
        test::runRubble("run " + dir + "/s.json --out " + dir + "/t.csv --every 2 --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("two balls: 5 steps, 2 bodies"), std::string::npos) << r.output;
    const std::vector<std::string> l = lines(test::readText(dir + "/t.csv"));
    ASSERT_EQ(l.size(), 1u + 2u * 3u); // header, steps 0, 2, 4
    EXPECT_EQ(l[0], "step,time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
    EXPECT_EQ(l[1], "0,0,a,0,10,0,1,0,0,0,0,0,0,0,0,0");
    EXPECT_EQ(l[3].substr(0, 7), "2,0.02,");
    EXPECT_EQ(l[6].substr(0, 9), "4,0.04,b,");
    EXPECT_FALSE(std::ifstream(dir + "/t.csv.partial").good());
}

TEST(RunCommand, WritesJsonLinesWithTheSameFields) {
    const std::string dir = test::tempDir("run_jsonl");
    test::writeText(dir + "/s.json", kScene);
    const test::CommandResult r =
        test::runRubble("run " + dir + "/s.json --out " + dir + "/t.jsonl --steps 3 --quiet");
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
    test::writeText(dir + "/s.json", kScene);
    const test::CommandResult r =
        test::runRubble("run " + dir + "/s.json --metrics " + dir + "/m.json --quiet");
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

TEST(RunCommand, NonFiniteStateStopsCleanlyAndKeepsWhatWasWritten) {
    const std::string dir = test::tempDir("run_nan");
    std::string scene = kScene;
    scene.replace(scene.find("\"linear_velocity\": [1, 0, 0]"), 28,
                  "\"linear_velocity\": [3e38, 0, 0]");
    test::writeText(dir + "/s.json", scene);
    const test::CommandResult r =
        test::runRubble("run " + dir + "/s.json --out " + dir + "/t.csv --quiet --dt 1");
    EXPECT_EQ(r.exitCode, 3) << r.output;
    EXPECT_NE(r.output.find("body b"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("not finite after step"), std::string::npos) << r.output;
    const std::vector<std::string> l = lines(test::readText(dir + "/t.csv"));
    EXPECT_GE(l.size(), 3u); // the header and step 0 at least
    for (std::size_t i = 1; i < l.size(); ++i)
        EXPECT_EQ(l[i].find("inf"), std::string::npos) << "a non-finite row was written: " << l[i];
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

} // namespace
} // namespace rubble
