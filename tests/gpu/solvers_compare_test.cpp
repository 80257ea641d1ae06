// tests/gpu/solvers_compare_test.cpp: the comparison commands with the device: `rubble solvers`
// writes a row per solver, backend and iteration (the device twins agreeing with the CPU), and
// `rubble compare` of the cpu backend against the opencl backend finds a small divergence.
#include <map>
#include <sstream>

#include "gpu_fixture.h"

namespace rubble {
namespace {

// Three frictionless boxes on each other, then a fourth dropped beside them.
const char* kScene = R"({"format": "rubble-scene", "version": 1, "name": "stack",
  "simulation": {"dt": 0.016666667, "collision": {"particle_spacing": 0.25},
                 "solver": {"type": "pgs", "iterations": 10}},
  "materials": {"default": {"friction": 0}},
  "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
  "bodies": [{"name": "floor", "shape": "floor", "static": true},
             {"name": "a", "shape": "crate", "mass": 1, "position": [0, 0.5, 0]},
             {"name": "b", "shape": "crate", "mass": 1, "position": [0, 1.5, 0]},
             {"name": "c", "shape": "crate", "mass": 1, "position": [0, 2.5, 0]},
             {"name": "d", "shape": "crate", "mass": 1, "position": [1.5, 1.0, 0]}]})";

class SolversCompare : public test::GpuTest {
  protected:
    void SetUp() override {
        test::GpuTest::SetUp();
        dir_ = test::tempDir(::testing::UnitTest::GetInstance()->current_test_info()->name());
        test::writeText(dir_ + "/s.json", kScene);
    }
    std::string dir_;
};

TEST_F(SolversCompare, SolversWritesEverySolverEveryIteration) {
    const test::CommandResult r = test::runRubble("solvers " + dir_ +
                                                  "/s.json --step 40 "
                                                  "--iterations 20 --csv " +
                                                  dir_ + "/s.csv");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("frictionless: normal rows only"), std::string::npos) << r.output;
    const auto rows = test::csvRows(test::readText(dir_ + "/s.csv"));
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows[0], (std::vector<std::string>{"solver", "backend", "iteration", "residual",
                                                 "complementarity", "velocity_error"}));
    std::map<std::string, int> count;
    std::map<std::string, std::vector<double>> residual;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        ASSERT_EQ(rows[i].size(), 6u) << i;
        const std::string key = rows[i][0] + "/" + rows[i][1];
        ++count[key];
        residual[key].push_back(std::stod(rows[i][3]));
        if (rows[i][0] != "lemke") {
            EXPECT_EQ(std::stoi(rows[i][2]), count[key]);
        }
    }
    const std::map<std::string, int> expected = {{"pgs/cpu", 20},           {"jacobi/cpu", 20},
                                                 {"jacobi/opencl", 20},     {"lcp-jacobi/cpu", 20},
                                                 {"lcp-jacobi/opencl", 20}, {"lemke/cpu", 1}};
    EXPECT_EQ(count, expected);
    // Lemke is exact; the device twins follow their CPU solvers.
    EXPECT_LT(residual["lemke/cpu"][0], 1e-9);
    for (const char* solver : {"jacobi", "lcp-jacobi"})
        for (std::size_t k = 0; k < 20; ++k)
            EXPECT_NEAR(residual[std::string(solver) + "/opencl"][k],
                        residual[std::string(solver) + "/cpu"][k],
                        1e-4 * residual[std::string(solver) + "/cpu"][k])
                << solver << " iteration " << k + 1;
}

// The same particle scene on both backends: in deterministic mode the jacobi device pipeline is
// its CPU twin's (up to float round-off), lcp-jacobi's too; through a second the bodies stay
// within a micrometre, closer than one sweep more or less of either solver leaves them.
TEST_F(SolversCompare, CompareCpuAgainstOpenclIsSmall) {
    for (const char* solver : {"jacobi", "lcp-jacobi"}) {
        SCOPED_TRACE(solver);
        const std::string side =
            std::string("collision=particles,solver=") + solver + ",deterministic=true,backend=";
        const test::CommandResult r =
            test::runRubble("compare " + dir_ + "/s.json --steps 60 --a " + side + "cpu --b " +
                            side + "opencl --csv " + dir_ + "/c.csv");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const auto rows = test::csvRows(test::readText(dir_ + "/c.csv"));
        ASSERT_EQ(rows.size(), 62u);
        double largest = 0.0;
        int contacts = 0;
        for (std::size_t i = 1; i < rows.size(); ++i) {
            largest = std::max(largest, std::stod(rows[i][2]));
            contacts = std::max(contacts, std::stoi(rows[i][16]));
            EXPECT_EQ(rows[i][16], rows[i][17]) << "contacts of both sides, step " << rows[i][0];
        }
        EXPECT_LT(largest, 1e-6) << "m\n" << r.output;
        EXPECT_GT(contacts, 40);
    }
}

} // namespace
} // namespace rubble
