// tests/unit/solver_suite_test.cpp: mirrors host/tools/solver_suite.cpp and `rubble solvers
// --suite`: two scenes of the set for a few steps, every CPU solver, the CSV's columns.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rubble/tools.h"
#include "support/test_util.h"

namespace rubble {
namespace {

std::string solverScene(const std::string& name) {
    return std::string(RUBBLE_SOURCE_DIR) + "/scenes/solver/" + name + ".json";
}

TEST(SolverSuite, CommandWritesEverySolversRowWithItsColumns) {
    const std::string dir = test::tempDir("suite");
    for (const char* name : {"stack_20", "heavy_on_light_1000"})
        test::runShell("cp '" + solverScene(name) + "' '" + dir + "/'");
    const std::string csv = dir + "/suite.csv";
    const test::CommandResult r =
        test::runRubble("solvers --suite " + dir + " --steps 5 --paths cpu --csv " + csv);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::vector<std::vector<std::string>> rows = test::csvRows(test::readText(csv));
    ASSERT_EQ(rows.size(), 1u + 2u * 4u) << "a header, then 2 scenes x 4 solvers";
    EXPECT_EQ(rows[0],
              (std::vector<std::string>{"scene", "solver", "path", "settings", "steps", "stands",
                                        "top_drift", "top_creep", "penetration", "energy_gained",
                                        "joint_error", "ms_per_step", "skipped"}));
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const std::vector<std::string>& row = rows[i];
        ASSERT_EQ(row.size(), 13u) << r.output;
        EXPECT_EQ(row[2], "cpu");
        EXPECT_EQ(row[4], "5") << row[0] << " " << row[1] << ": every step ran";
        // Five steps from rest: the top body has settled by a few centimetres at most.
        EXPECT_EQ(row[5], "yes") << row[0] << " " << row[1];
        EXPECT_LT(std::stod(row[6]), 0.1) << row[0] << " " << row[1];
        EXPECT_GE(std::stod(row[7]), 0.0) << row[0] << " " << row[1];
        EXPECT_LT(std::stod(row[7]), 0.1) << row[0] << " " << row[1];
        EXPECT_GT(std::stod(row[11]), 0.0);
        EXPECT_EQ(row[1] == "soft-step" ? "substeps=5 relax=1" : "iterations=10", row[3]);
    }
    EXPECT_NE(r.output.find("| stack_20 | soft-step | cpu |"), std::string::npos) << r.output;
}

// Equal cost: 4 passes are 2 substeps of one biased and one relax pass. A scene with joints
// gives the solvers without joint rows a row saying so instead of a run.
TEST(SolverSuite, EqualPassesAndJointsOnlyWhereThereAreJointRows) {
    SuiteOptions o;
    o.scenes = {solverScene("chain_40")};
    o.steps = 3;
    o.passes = 4;
    o.paths = {"cpu"};
    Result<std::vector<SuiteRow>> rows = runSolverSuite(o);
    ASSERT_TRUE(rows.ok()) << rows.error().describe();
    ASSERT_EQ(rows->size(), 4u);
    for (const SuiteRow& r : *rows) {
        if (r.solver == "jacobi" || r.solver == "lcp-jacobi") {
            EXPECT_EQ(r.steps, 0);
            EXPECT_NE(r.skipped.find("joint"), std::string::npos) << r.skipped;
            continue;
        }
        EXPECT_TRUE(r.skipped.empty()) << r.solver << ": " << r.skipped;
        EXPECT_EQ(r.steps, 3);
        EXPECT_EQ(r.settings, r.solver == "soft-step" ? "substeps=2 relax=1" : "iterations=4");
        EXPECT_GT(r.jointError, 0.0) << r.solver << ": the chain's joints are measured";
        EXPECT_LT(r.jointError, 0.05) << r.solver;
    }
    o.passes = 0;
    EXPECT_EQ(runSolverSuite(o).error().where, "--passes");
}

} // namespace
} // namespace rubble
