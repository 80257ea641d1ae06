// tests/unit/compare_command_test.cpp: `rubble compare` on the cpu backend: a scene against
// itself does not diverge, two solvers do, its CSV has a row per step, a bad KEY=VALUE is exit
// status 2 naming it, and --plot draws a PNG; `rubble solvers` refuses what it cannot do.
#include <cmath>
#include <sstream>
#include <utility>

#include <gtest/gtest.h>

#include "support/ci.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// Two boxes falling onto a floor and one onto the other.
const char* kScene = R"({"format": "rubble-scene", "version": 1, "name": "drop",
  "simulation": {"dt": 0.016666667, "steps": 60},
  "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
  "bodies": [{"name": "floor", "shape": "floor", "static": true},
             {"name": "a", "shape": "crate", "mass": 1, "position": [0, 0.6, 0]},
             {"name": "b", "shape": "crate", "mass": 1, "position": [0.2, 1.8, 0.1],
              "orientation": [0.98, 0.1, 0.1, 0.1]}]})";

class CompareCommand : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = test::tempDir(::testing::UnitTest::GetInstance()->current_test_info()->name());
        test::writeText(dir_ + "/s.json", kScene);
    }
    test::CommandResult compare(const std::string& args) {
        return test::runRubble("compare " + dir_ + "/s.json " + args);
    }
    std::string dir_;
};

TEST_F(CompareCommand, ASceneAgainstItselfDoesNotDiverge) {
    const test::CommandResult r =
        compare("--steps 40 --a solver=pgs --b solver=pgs --csv " + dir_ + "/c.csv");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto rows = test::csvRows(test::readText(dir_ + "/c.csv"));
    ASSERT_EQ(rows.size(), 42u); // header, steps 0 to 40
    ASSERT_EQ(rows[0][2], "position_max");
    ASSERT_EQ(rows[0][4], "angle_max");
    for (std::size_t i = 1; i < rows.size(); ++i) {
        EXPECT_EQ(std::stod(rows[i][2]), 0.0) << "step " << rows[i][0];
        EXPECT_EQ(std::stod(rows[i][4]), 0.0) << "step " << rows[i][0];
        EXPECT_EQ(rows[i][6], rows[i][7]) << "kinetic energy, step " << rows[i][0];
    }
    // The table: a heading and a row every 10% of the steps.
    EXPECT_NE(r.output.find("pos max"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\n    40 "), std::string::npos) << r.output;
}

TEST_F(CompareCommand, TwoSolversDivergeAndBothStayFinite) {
    const test::CommandResult r = compare(
        "--steps 60 --a solver=pgs --b solver=lcp-jacobi,iterations=20 --csv " + dir_ + "/c.csv");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto rows = test::csvRows(test::readText(dir_ + "/c.csv"));
    ASSERT_EQ(rows.size(), 62u);
    double widest = 0.0;
    for (std::size_t i = 1; i < rows.size(); ++i) widest = std::max(widest, std::stod(rows[i][2]));
    EXPECT_GT(std::stod(rows.back()[2]), 0.0) << "m: the solvers part";
    // Standing, the two stacks part by centimetres as b settles on a (a fall is a metre).
    EXPECT_LT(widest, 0.1) << "m: two standing stacks part by little";
    EXPECT_GT(std::stod(rows.back()[16]), 0.0); // contacts on side a
    EXPECT_GT(std::stod(rows.back()[17]), 0.0); // contacts on side b
    // Both stacks stand: the two settings through the library leave b resting on a, a on the
    // floor, at the end of the compared steps.
    for (const auto& [solver, iterations] :
         {std::pair{SolverType::Pgs, 10}, std::pair{SolverType::LcpJacobi, 20}}) {
        Result<Scene> scene = parseScene(kScene, "s.json", ".");
        ASSERT_TRUE(scene.ok()) << scene.error().describe();
        scene->simulation.solver.type = solver;
        scene->simulation.solver.iterations = iterations;
        Result<World> world = World::create(*scene);
        ASSERT_TRUE(world.ok()) << world.error().describe();
        ASSERT_TRUE(test::stepWorld(*world, 60));
        const BodyState a = world->body(1), b = world->body(2);
        EXPECT_NEAR(a.position.y, 0.5f, 0.01f) << "m: a on the floor, solver " << int(solver);
        EXPECT_NEAR(b.position.y - a.position.y, 1.0f, 0.01f)
            << "m: b on a, solver " << int(solver);
        EXPECT_LT(std::hypot(b.position.x - a.position.x, b.position.z - a.position.z), 0.4f)
            << "m: b's centre over a's top face, solver " << int(solver);
    }
}

TEST_F(CompareCommand, BadSettingsAreExitStatus2NamingThem) {
    const std::pair<std::string, std::string> cases[] = {
        {"--a solver=foo --b solver=pgs", "--a solver=foo"},
        {"--a solver=pgs --b colour=red", "--b colour=red: unknown key"},
        {"--a iterations=0 --b solver=pgs", "--a iterations=0"},
        {"--a dt=-1 --b solver=pgs", "--a dt=-1"},
        {"--a solver --b solver=pgs", "--a solver: expected KEY=VALUE"},
        {"--a deterministic=maybe --b solver=pgs", "--a deterministic=maybe"},
        {"--a dt=0.01 --b dt=0.015", "must be equal or one a whole multiple"},
    };
    for (const auto& [args, message] : cases) {
        const test::CommandResult r = compare("--steps 2 " + args);
        EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    }
}

TEST_F(CompareCommand, DifferentTimeStepsCompareAtTheSameTimes) {
    const test::CommandResult r =
        compare("--steps 10 --a dt=0.02 --b dt=0.01 --csv " + dir_ + "/c.csv");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto rows = test::csvRows(test::readText(dir_ + "/c.csv"));
    ASSERT_EQ(rows.size(), 12u);
    EXPECT_NEAR(std::stod(rows.back()[1]), 0.2, 1e-6);
}

TEST_F(CompareCommand, PlotDrawsAPng) {
    if (test::runShell("/usr/bin/python3 -c 'import matplotlib'").exitCode != 0) {
        if (test::inCi())
            FAIL() << "CI is set and /usr/bin/python3 has no matplotlib (scripts/setup.sh)";
        GTEST_SKIP() << "/usr/bin/python3 with matplotlib is not installed";
    }
    const test::CommandResult r =
        compare("--steps 10 --a solver=pgs --b solver=jacobi --plot " + dir_ + "/c.png");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string png = test::readText(dir_ + "/c.png");
    ASSERT_GT(png.size(), 1000u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
}

TEST(SolversCommand, BadArgumentsAreExitStatus2) {
    const std::string dir = test::tempDir("solvers_bad");
    test::writeText(dir + "/s.json", kScene);
    const test::CommandResult step0 = test::runRubble("solvers " + dir + "/s.json --step 0");
    EXPECT_EQ(step0.exitCode, 2) << step0.output;
    EXPECT_NE(step0.output.find("--step"), std::string::npos) << step0.output;
    // Before the boxes land there is nothing to solve.
    const test::CommandResult early = test::runRubble("solvers " + dir + "/s.json --step 1");
    EXPECT_EQ(early.exitCode, 2) << early.output;
    EXPECT_NE(early.output.find("no contacts"), std::string::npos) << early.output;
    const test::CommandResult k0 = test::runRubble("solvers " + dir + "/s.json --iterations 0");
    EXPECT_EQ(k0.exitCode, 2) << k0.output;
}

} // namespace
} // namespace rubble
