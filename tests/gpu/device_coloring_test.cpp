// tests/gpu/device_coloring_test.cpp: the device's plan of the colored solve
// (kernels/coloring.cl, host/gpu/pgs_device_plan.cpp): a valid coloring (no two elements of a
// color share a moving body, every element once, each set in element order, rows packed), the
// same plan and the same steps run after run, and colored scenes that stand on it.
#include <algorithm>
#include <cstring>
#include <map>
#include <set>

#include "gpu_fixture.h"
#include "support/physics_cases.h"
#include "rubble/shared/pgs_coloring.h"
#include "support/floor_reach.h"

namespace rubble {
namespace {

// The plan of one step on the state as loaded, as the device holds it.
struct DevicePlan {
    std::vector<cl_uint> starts, colorOf;
    std::vector<shared::PgsElement> elements;
    std::vector<cl_uint> summaries; ///< the pairs' summary words, read on the host
};

class DeviceColoring : public test::GpuTest {
  protected:
    // A world of `scene` on the device with SAT and `solver`, every element colored by the
    // device.
    World world(Scene scene, SolverType solver = SolverType::Pgs) {
        scene.simulation.backend = Backend::OpenCl;
        scene.simulation.collision.method = CollisionMethod::Sat;
        scene.simulation.solver.type = solver;
        RunOptions run;
        run.pgsBlocks = 0;
        run.pgsColoring = PgsColoring::Device;
        return worldOf(scene, run);
    }
    // The device's stages of a step of `json` on its state as loaded, up to the plan.
    DevicePlan planOnce(const std::string& json) {
        test::StageInput in = test::stageInput(json);
        const StepParams params = in.params();
        std::unique_ptr<test::DeviceStage> made = satStage(in, 0, true);
        test::DeviceStage& p = *made;
        DevicePlan plan;
        auto run = [&]() -> Status {
            RUBBLE_TRY(p.resetStatus());
            RUBBLE_TRY(p.broadPhase(params.dt));
            RUBBLE_TRY(p.narrowPhase(params.dt));
            RUBBLE_TRY(p.summarizePairs(params));
            RUBBLE_TRY(p.readStatus());
            RUBBLE_TRY(p.colorPgs());
            RUBBLE_TRY(p.finish());
            const std::uint32_t pairs =
                std::min(p.q().lastStatus().pairs, p.pairs.current.capacity);
            Result<std::vector<cl_uint>> starts = p.pgs.downloadColorStarts(p.q());
            RUBBLE_TRY(starts);
            Result<std::vector<cl_uint>> colorOf = p.pgs.downloadColorOf(p.q(), pairs);
            RUBBLE_TRY(colorOf);
            Result<std::vector<cl_uint>> summaries =
                gpu::download<cl_uint>(p.q().c(), p.pairs.summaries, pairs);
            RUBBLE_TRY(summaries);
            Result<std::vector<shared::PgsElement>> elements =
                p.pgs.downloadElements(p.q(), (*starts)[RUBBLE_PGS_COLORS + 1]);
            RUBBLE_TRY(elements);
            plan = {*starts, *colorOf, *elements, *summaries};
            return {};
        };
        const Status s = run();
        EXPECT_TRUE(s.ok()) << s.error().describe();
        EXPECT_TRUE(p.pgs.devicePlans());
        return plan;
    }
    World sceneFile(const char* name, SolverType solver = SolverType::Pgs) {
        Result<Scene> scene = loadScene(std::string(RUBBLE_SOURCE_DIR) + "/scenes/" + name);
        EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
        if (!scene.ok()) std::abort();
        return world(*scene, solver);
    }
};

// Unit crates in a block five wide, three high and four deep, on a floor: each crate touches up
// to six others, and the pairs hold more than the colors' worth of elements on a body.
std::string crateBlock() { return test::crateBlockScene(5, 3, 4); }

// Every pair with points is an element once; within a color no two elements share a body that
// moves; each color and the overflow set keep element order (pair order here: no joints); each
// element's rows are a run of its points, the runs packed in element order.
TEST_F(DeviceColoring, ColorsShareNoMovingBodyAndHoldEveryElementOnce) {
    const DevicePlan plan = planOnce(crateBlock());
    ASSERT_EQ(plan.starts.size(), std::size_t(RUBBLE_PGS_COLOR_STARTS_WORDS));
    const std::uint32_t total = plan.starts[RUBBLE_PGS_COLORS + 1];
    std::set<std::uint32_t> expected;
    std::uint32_t points = 0;
    for (std::uint32_t p = 0; p < plan.summaries.size(); ++p)
        if (plan.summaries[p] & RUBBLE_PGS_POINTS) {
            expected.insert(p);
            points += plan.summaries[p] & RUBBLE_PGS_POINTS;
        }
    ASSERT_GE(expected.size(), 130u); // 20 on the floor, and between the 60 crates
    ASSERT_EQ(plan.elements.size(), std::size_t(total));
    EXPECT_EQ(total, expected.size());
    std::set<std::uint32_t> placed;
    std::uint32_t nextRow = 0, colorsUsed = 0;
    for (std::uint32_t k = 0; k <= RUBBLE_PGS_COLORS; ++k) {
        const std::uint32_t from = plan.starts[k], to = plan.starts[k + 1];
        ASSERT_LE(from, to);
        EXPECT_EQ(plan.starts[RUBBLE_PGS_COLOR_ROW_STARTS + k], nextRow) << "set " << k;
        colorsUsed += from < to && k < RUBBLE_PGS_COLORS;
        std::set<std::uint32_t> bodies;
        for (std::uint32_t i = from; i < to; ++i) {
            const shared::PgsElement& e = plan.elements[i];
            ASSERT_LT(e.id, plan.summaries.size());
            EXPECT_TRUE(placed.insert(e.id).second) << "pair " << e.id << " twice";
            EXPECT_EQ(e.rows, plan.summaries[e.id]);
            // The overflow set: no color free, or none taken in the rounds.
            if (k == RUBBLE_PGS_OVERFLOW_SET) {
                EXPECT_TRUE(plan.colorOf[e.id] == k || plan.colorOf[e.id] == RUBBLE_PGS_UNCOLORED)
                    << "pair " << e.id;
            } else {
                EXPECT_EQ(plan.colorOf[e.id], k) << "pair " << e.id;
            }
            if (i > from) {
                EXPECT_LT(plan.elements[i - 1].id, e.id) << "set " << k;
            }
            const std::uint32_t n = e.rows & RUBBLE_PGS_POINTS;
            for (std::uint32_t r = 0; r < 4; ++r) EXPECT_EQ(e.normal[r], r < n ? nextRow + r : 0u);
            nextRow += n;
            if (k == RUBBLE_PGS_OVERFLOW_SET) continue; // in order on one work-item
            if (e.rows & RUBBLE_PGS_MOVES_A) {
                EXPECT_TRUE(bodies.insert(e.a).second) << "body " << e.a << " twice in " << k;
            }
            if (e.rows & RUBBLE_PGS_MOVES_B) {
                EXPECT_TRUE(bodies.insert(e.b).second) << "body " << e.b << " twice in " << k;
            }
        }
    }
    std::printf("elements by set:");
    for (std::uint32_t k = 0; k <= RUBBLE_PGS_COLORS; ++k)
        std::printf(" %u", plan.starts[k + 1] - plan.starts[k]);
    std::printf("\n");
    EXPECT_EQ(placed, expected);
    EXPECT_EQ(nextRow, points);
    EXPECT_EQ(plan.starts[RUBBLE_PGS_COLOR_STARTS_WORDS - 1], points);
    // A crate in the block touches up to six others and the floor: several colors.
    EXPECT_GE(colorsUsed, 4u);
    for (std::uint32_t p = 0; p < plan.summaries.size(); ++p)
        if (!expected.count(p)) {
            EXPECT_EQ(plan.colorOf[p], RUBBLE_PGS_NOT_ELEMENT) << p;
        }
}

// The same state gives the same colors, records and rows on two fresh queues, and a world stepped
// twice on its colors ends on the same bits: the rounds' atomics decide by priority, never by
// which work-item comes first.
TEST_F(DeviceColoring, TheSameInputGivesTheSameColorsAndSteps) {
    const DevicePlan a = planOnce(crateBlock()), b = planOnce(crateBlock());
    ASSERT_FALSE(a.elements.empty());
    EXPECT_EQ(a.starts, b.starts);
    EXPECT_EQ(a.colorOf, b.colorOf);
    ASSERT_EQ(a.elements.size(), b.elements.size());
    EXPECT_EQ(0, std::memcmp(a.elements.data(), b.elements.data(),
                             a.elements.size() * sizeof(shared::PgsElement)));

    Scene scene = sceneOf(crateBlock());
    scene.simulation.sleep = false;
    World first = world(scene), second = world(scene);
    for (int step = 1; step <= 60; ++step) {
        ASSERT_TRUE(first.step().ok()) << "step " << step;
        ASSERT_TRUE(second.step().ok()) << "step " << step;
    }
    for (std::uint32_t i = 0; i < first.bodyCount(); ++i)
        EXPECT_TRUE(test::sameBits(first.body(i), second.body(i))) << first.bodyName(i);
}

// pyramid_20 and stack_10 on the device's colors stand, sink no corner and fall asleep, with PGS
// and with the soft step (whose stack is kept awake); once asleep nothing more is launched.
TEST_F(DeviceColoring, ColoredPyramidAndStackStand) {
    for (const auto& [name, solver] : {std::pair{"pyramid_20.json", SolverType::Pgs},
                                       {"stack_10.json", SolverType::Pgs},
                                       {"pyramid_20.json", SolverType::SoftStep},
                                       {"stack_10.json", SolverType::SoftStep}}) {
        World w = sceneFile(name, solver);
        const std::vector<glm::vec3> start = test::positionsOf(w);
        for (int step = 0; step < 600; ++step) ASSERT_TRUE(w.step().ok()) << name;
        float moved = 0.0f;
        std::uint32_t dynamic = 0, asleep = 0;
        for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
            if (w.body(i).isStatic) continue;
            ++dynamic;
            asleep += w.body(i).asleep;
            moved = std::max(moved, glm::length(w.body(i).position - start[i]));
        }
        const test::FloorReach sunk = test::deepestBelowFloor(w);
        std::printf("[ %s, %s ] largest displacement %.4f m, %u of %u asleep, deepest corner "
                    "%.4f m below the floor\n",
                    name, solver == SolverType::Pgs ? "pgs" : "soft-step", moved, asleep, dynamic,
                    sunk.depth);
        EXPECT_LT(moved, 0.06f) << name;
        EXPECT_LT(sunk.depth, 0.006) << name << ": " << sunk.name << "'s lowest corner, m";
        EXPECT_EQ(asleep, dynamic) << name;
    }
}

} // namespace
} // namespace rubble
