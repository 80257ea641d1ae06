// tests/gpu/pgs_twin_test.cpp: projected Gauss-Seidel on the device against the CPU reference
// (PgsSolver): the same contact rows bit for bit from the same state, a small stack stepped on
// both (velocities within the tolerance of two sweep orders), and the shipped scenes that must
// stand, hold their joints and fall asleep on the device.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string_view>
#include <tuple>

#include "gpu_fixture.h"
#include "host/collision/sat_collision.h"
#include "host/dynamics/pgs_solver.h"
#include "support/floor_reach.h"
#include "support/physics_cases.h"

namespace rubble {
namespace {

class PgsTwin : public test::GpuTest {
  protected:
    // A world of `json` on the device with SAT and PGS, or on the CPU.
    // `blocks`: RunOptions::pgsBlocks (-1 as the device suits, 0 colors only).
    World world(const std::string& json, Backend backend, int blocks = -1) {
        return world(sceneOf(json), backend, blocks);
    }
    World world(const Scene& scene, Backend backend, int blocks = -1) {
        return worldOf(scene, backend, CollisionMethod::Sat, SolverType::Pgs, blocks);
    }
    // RagdollPileHoldsItsJointsAndSettlesOnTheDevice with `blocks` (RunOptions::pgsBlocks),
    // against the CPU's pile at 20 s (`cpu`), to the bit in the CPU's order.
    void ragdollPileSettles(int blocks, const World& cpu);
    World sceneFile(const char* name, Backend backend, int blocks = -1) {
        Result<Scene> scene = loadScene(std::string(RUBBLE_SOURCE_DIR) + "/scenes/" + name);
        EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
        if (!scene.ok()) std::abort();
        return world(*scene, backend, blocks);
    }
};

// Three crates stacked a little into each other and into the floor (pushes), a crate sliding
// at 3 m/s (the sliding tangent), a bouncy ball landing at 4 m/s (restitution) and a crate a few
// millimetres above the floor closing the gap at 1 m/s; turned a little, two materials.
const char* kRowScene = R"({"format": "rubble-scene", "version": 1, "name": "rows",
  "simulation": {"dt": 0.016666667, "solver": {"type": "pgs", "iterations": 10}},
  "materials": {"default": {"friction": 0.5, "restitution": 0.0},
                "bouncy": {"friction": 0.8, "restitution": 0.7}},
  "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
             "ball": {"type": "sphere", "radius": 0.3}},
  "bodies": [
    {"name": "floor", "shape": "ground", "static": true},
    {"name": "s0", "shape": "crate", "mass": 2, "position": [0, 0.49, 0]},
    {"name": "s1", "shape": "crate", "mass": 2, "position": [0.05, 1.47, 0],
     "orientation": [0.9998, 0, 0.02, 0]},
    {"name": "s2", "shape": "crate", "mass": 2, "position": [-0.04, 2.45, 0.03]},
    {"name": "slide", "shape": "crate", "mass": 3, "position": [4, 0.499, 0],
     "linear_velocity": [3, 0, 0.5]},
    {"name": "ball", "shape": "ball", "material": "bouncy", "mass": 1, "position": [-4, 0.295, 0],
     "linear_velocity": [0, -4, 0], "angular_velocity": [0, 0, 2]},
    {"name": "gap", "shape": "crate", "mass": 1, "position": [0, 0.503, 4],
     "orientation": [0.9999, 0.01, 0, 0], "linear_velocity": [0, -1, 0]}]})";

// A scene of unit crates ("crate", 1 m on a side) on a floor, at 60 Hz with 10 sweeps, every
// material of friction `friction` and restitution 0: `bodies` follow the floor in its list.
std::string cratesOnTheFloor(float friction, const std::string& bodies) {
    return R"({"format": "rubble-scene", "version": 1, "name": "crates",
      "simulation": {"dt": 0.016666667, "solver": {"iterations": 10}},
      "materials": {"default": {"friction": )" +
           std::to_string(friction) + R"(, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},)" +
           bodies + "]}";
}

// The device's stages of a step on the state as loaded, up to the split of its elements into
// blocks and colors (colorPgs).
Status colorStep(test::DeviceStage& p, const StepParams& params) {
    RUBBLE_TRY(p.resetStatus());
    RUBBLE_TRY(p.broadPhase(params.dt));
    RUBBLE_TRY(p.narrowPhase(params.dt));
    RUBBLE_TRY(p.summarizePairs(params));
    RUBBLE_TRY(p.readStatus());
    return p.colorPgs();
}

bool sameBits(shared::float4 a, shared::float4 b) {
    return a.x == b.x && a.y == b.y && a.z == b.z && std::memcmp(&a, &b, 12) == 0;
}
bool sameBits(Lanes a, shared::float4 b) {
    return sameBits(shared::float4{a[0], a[1], a[2], 0.0f}, b);
}
bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// The device's buildPgsRows and the CPU's buildContactRows on the same state give the same
// rows, bit for bit: both call pgsContactRowItem.
TEST_F(PgsTwin, RowsAreTheCpuRowsBitForBit) {
    test::StageInput in = test::stageInput(kRowScene);
    const StepParams params = in.params();
    // The CPU: its collision and rows on the state as loaded.
    SatCollision collision(ContactForm::Manifolds);
    StepContacts contacts;
    ASSERT_TRUE(collision.broadPhase(in.collisionScene(), in.bodies.view(), params, contacts).ok());
    ASSERT_TRUE(
        collision.narrowPhase(in.collisionScene(), in.bodies.view(), params, contacts).ok());
    PgsSolver cpu;
    const SolverScene solverScene{in.shapes,       in.scene.materials, in.surfaces,
                                  in.scene.joints, in.joined,          in.names};
    // Stages run alone take the loaded velocities as those before the forces, on both sides
    // (the device's uploadBodies writes them to its atStart).
    cpu.buildRows(solverScene, in.bodies.view(), in.bodies.velocities, contacts, params);
    const ContactRows& rows = cpu.cache().contacts;

    // The device: the same stages on the same arrays.
    std::unique_ptr<test::DeviceStage> made = satStage(in);
    test::DeviceStage& p = *made;
    const Status colored = colorStep(p, params);
    ASSERT_TRUE(colored.ok()) << colored.error().describe();
    ASSERT_TRUE(p.buildPgsRows(params).ok());
    ASSERT_TRUE(p.finish().ok());
    Result<std::vector<shared::PgsNormalRow>> normals = p.pgs.downloadNormalRows(p.q());
    Result<std::vector<shared::PgsFrictionRows>> frictions = p.pgs.downloadFrictionRows(p.q());
    Result<std::vector<shared::ContactManifold>> manifolds = p.downloadManifolds();
    ASSERT_TRUE(normals.ok() && frictions.ok() && manifolds.ok());

    // The device's rows by (a, b, feature): the point's place (its normal row's, its friction
    // rows').
    std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> device;
    for (const shared::PgsElement& e : p.pgs.elements()) {
        if (e.id & RUBBLE_PGS_JOINT_ELEMENT) continue;
        const shared::ContactManifold& m = (*manifolds)[e.id];
        for (std::uint32_t k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k)
            device[{e.a, e.b, m.features[k]}] = e.normal[k];
    }
    ASSERT_EQ(device.size(), rows.size());
    ASSERT_GE(rows.size(), 16u); // the stack's faces, the slider, the ball, the gap
    int pushing = 0, bouncing = 0, gaps = 0, sliding = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const ContactKey& key = rows.keys[i];
        const auto found = device.find({key.a, key.b, key.feature});
        ASSERT_NE(found, device.end()) << "row of " << key.a << "-" << key.b;
        const shared::PgsNormalRow& dn = (*normals)[found->second];
        const shared::PgsFrictionRows& df = (*frictions)[found->second];
        const NormalRow& n = rows.normals[i];
        const FrictionRows& f = rows.frictions[i];
        const std::string where = "row of " + std::to_string(key.a) + "-" + std::to_string(key.b);
        EXPECT_TRUE(sameBits(n.normal, dn.normal)) << where;
        EXPECT_TRUE(sameBits(n.crossA, dn.crossA) && sameBits(n.crossB, dn.crossB)) << where;
        EXPECT_TRUE(sameBits(n.turnA, dn.turnA) && sameBits(n.turnB, dn.turnB)) << where;
        EXPECT_TRUE(sameBits(n.mass, dn.mass.x)) << where;
        EXPECT_TRUE(sameBits(n.targetSpeed, dn.speeds.x))
            << where << ": target " << n.targetSpeed << " vs " << dn.speeds.x;
        EXPECT_TRUE(sameBits(n.pushSpeed, dn.speeds.y)) << where;
        EXPECT_TRUE(sameBits(n.bounceSpeed, dn.mass.y) && sameBits(n.bounceLift, dn.mass.z))
            << where << ": bounce " << n.bounceSpeed << ", " << n.bounceLift << " vs " << dn.mass.y
            << ", " << dn.mass.z;
        for (int d = 0; d < 2; ++d) {
            EXPECT_TRUE(sameBits(f.tangent[d], df.tangent[d])) << where << " tangent " << d;
            EXPECT_TRUE(sameBits(f.turnA[d], df.turnA[d]) && sameBits(f.turnB[d], df.turnB[d]))
                << where << " tangent " << d;
        }
        EXPECT_TRUE(sameBits(f.mass[0], df.mass.x) && sameBits(f.mass[1], df.mass.y)) << where;
        pushing += n.pushSpeed > 0.0f;
        bouncing += n.bounceSpeed > 0.0f && n.bounceLift > 0.0f;
        gaps += n.targetSpeed < 0.0f;
        sliding += std::abs(f.tangent[0][1]) < 0.5f && f.tangent[0][0] > 0.9f;
    }
    // Every kind of row was compared.
    EXPECT_GT(pushing, 0);
    EXPECT_GT(bouncing, 0);
    EXPECT_GT(gaps, 0);
    EXPECT_GT(sliding, 0);
}

// Three crates dropped 2 cm onto the floor and onto each other, stepped 40 times on both. The
// device sweeps color by color where the CPU sweeps every normal row then every friction pair,
// so the two agree to the solve's convergence, not to the bit: with 500 sweeps both reach the
// same impulses (velocities within 5e-5 m/s, positions within a micrometre at every step); with
// the scene's 10 the sweep orders show while the crates land and rock (within 0.1 m/s and 5 mm),
// and both come to rest stacked.
TEST_F(PgsTwin, AStackOfThreeMatchesTheCpu) {
    const std::string scene = R"({"format": "rubble-scene", "version": 1, "name": "stack3",
      "simulation": {"dt": 0.016666667, "solver": {"iterations": ITERATIONS}},
      "materials": {"default": {"friction": 0.5, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
        {"name": "c0", "shape": "crate", "mass": 2, "position": [0, 0.52, 0]},
        {"name": "c1", "shape": "crate", "mass": 2, "position": [0.1, 1.54, 0.05],
         "orientation": [0.9999, 0, 0.0141, 0]},
        {"name": "c2", "shape": "crate", "mass": 2, "position": [-0.05, 2.56, 0]}]})";
    struct Run {
        const char* iterations;
        float velocity, position; // the bounds, m/s and m
    };
    for (const Run& run : {Run{"500", 5e-5f, 1e-6f}, Run{"10", 0.1f, 5e-3f}}) {
        std::string json = scene;
        json.replace(json.find("ITERATIONS"), 10, run.iterations);
        World cpu = world(json, Backend::Cpu), device = world(json, Backend::OpenCl);
        float largestSpeed = 0.0f, largestApart = 0.0f;
        for (int step = 1; step <= 40; ++step) {
            ASSERT_TRUE(cpu.step().ok());
            ASSERT_TRUE(device.step().ok());
            for (std::uint32_t i = 1; i < cpu.bodyCount(); ++i) {
                const BodyState c = cpu.body(i), d = device.body(i);
                const float dv = std::max(glm::length(c.linearVelocity - d.linearVelocity),
                                          glm::length(c.angularVelocity - d.angularVelocity));
                const float dx = glm::length(c.position - d.position);
                EXPECT_LT(dv, run.velocity) << cpu.bodyName(i) << " step " << step;
                EXPECT_LT(dx, run.position) << cpu.bodyName(i) << " step " << step;
                largestSpeed = std::max(largestSpeed, dv);
                largestApart = std::max(largestApart, dx);
            }
        }
        std::printf("[ stack of three, %s sweeps ] largest velocity difference %.3g m/s, "
                    "position %.3g m\n",
                    run.iterations, largestSpeed, largestApart);
        // Both stand: the top crate's centre 2.5 m up, within the slop.
        EXPECT_NEAR(cpu.body(3).position.y, 2.5f, 0.01f);
        EXPECT_NEAR(device.body(3).position.y, 2.5f, 0.01f);
    }
}

// The split into blocks, on a 5 x 2 x 4 block of touching crates in 4 blocks: every element of
// the step placed once; the blocks share no body that moves (they run side by side), and each
// holds its elements in pair order (the CPU's order); the elements between blocks colored, no
// two of a launch on one moving body; every point's rows at a place of their own, a color's
// element's in a run, a block's by point.
TEST_F(PgsTwin, BlocksShareNoMovingBodyAndPlaceEveryElementOnce) {
    const std::string json = test::crateBlockScene(5, 2, 4);
    test::StageInput in = test::stageInput(json);
    const StepParams params = in.params();
    std::unique_ptr<test::DeviceStage> made = satStage(in, 4);
    test::DeviceStage& p = *made;
    const Status colored = colorStep(p, params);
    ASSERT_TRUE(colored.ok()) << colored.error().describe();
    ASSERT_TRUE(p.finish().ok());
    const gpu::PgsSolve& g = p.pgs;

    // Every element once.
    std::map<std::uint32_t, gpu::ColorElement> byId;
    for (const gpu::ColorElement& x : g.stepElements()) byId[x.id] = x;
    ASSERT_EQ(byId.size(), g.stepElements().size());
    ASSERT_GE(byId.size(), 60u); // 40 on the floor, and between the crates
    ASSERT_EQ(g.elements().size(), byId.size());
    std::set<std::uint32_t> placed;
    for (const shared::PgsElement& e : g.elements()) EXPECT_TRUE(placed.insert(e.id).second);
    EXPECT_EQ(placed.size(), byId.size());

    // The blocks: one launch first, then colors.
    ASSERT_FALSE(g.launches().empty());
    const gpu::PgsLaunch& blocks = g.launches()[0];
    ASSERT_EQ(blocks.mode, RUBBLE_PGS_BLOCKS);
    ASSERT_EQ(blocks.blocks, 4u);
    // The starts of the four blocks and the end, then each block's passes over its points.
    ASSERT_EQ(g.blockStarts().size(), 9u);
    EXPECT_EQ(g.blockStarts()[4], blocks.count);
    std::map<std::uint32_t, std::uint32_t> blockOfBody;
    for (std::uint32_t b = 0; b < 4; ++b) {
        EXPECT_LT(g.blockStarts()[b], g.blockStarts()[b + 1]) << "block " << b << " empty";
        for (std::uint32_t i = g.blockStarts()[b]; i < g.blockStarts()[b + 1]; ++i) {
            const shared::PgsElement& e = g.elements()[i];
            if (i > g.blockStarts()[b]) {
                EXPECT_LT(g.elements()[i - 1].id, e.id); // pair order
            }
            const gpu::ColorElement& x = byId[e.id];
            for (const auto& [body, moves] : {std::pair{x.a, x.movesA}, {x.b, x.movesB}}) {
                if (!moves) continue;
                const auto [it, added] = blockOfBody.emplace(body, b);
                EXPECT_EQ(it->second, b) << "body " << body << " in blocks " << it->second
                                         << " and " << b;
            }
        }
    }
    // Between the blocks: colored, and some are (the crates at the cuts).
    ASSERT_GE(g.launches().size(), 2u);
    for (std::size_t k = 1; k < g.launches().size(); ++k) {
        const gpu::PgsLaunch& l = g.launches()[k];
        EXPECT_NE(l.mode, RUBBLE_PGS_BLOCKS);
        if (l.mode == RUBBLE_PGS_SERIAL) continue; // run in order: may share bodies
        std::set<std::uint32_t> bodies;
        for (std::uint32_t i = l.first; i < l.first + l.count; ++i) {
            const gpu::ColorElement& x = byId[g.elements()[i].id];
            for (const auto& [body, moves] : {std::pair{x.a, x.movesA}, {x.b, x.movesB}}) {
                if (!moves) continue;
                EXPECT_TRUE(bodies.insert(body).second) << "launch " << k;
            }
        }
    }
    // The rows before each element: its points' and those before it, in the elements' order.
    std::uint32_t row = 0;
    for (std::size_t i = 0; i < g.elements().size(); ++i) {
        EXPECT_EQ(g.rowsBefore()[i], row);
        row += g.elements()[i].rows & RUBBLE_PGS_POINTS;
    }
    EXPECT_EQ(row, g.rowCount());
    // The points' rows: each place once; a block's by point from its first row (every element's
    // first point, then every second, ...), so that its passes read them front to back; a
    // color's element's in a run from the rows before it.
    auto points = [](const shared::PgsElement& e) { return e.rows & RUBBLE_PGS_POINTS; };
    std::set<std::uint32_t> normals;
    std::uint32_t multiPoint = 0;
    for (std::uint32_t b = 0; b < 4; ++b) {
        const std::uint32_t from = g.blockStarts()[b], to = g.blockStarts()[b + 1];
        std::uint32_t most = 1;
        for (std::uint32_t i = from; i < to; ++i) most = std::max(most, points(g.elements()[i]));
        EXPECT_EQ(g.blockStarts()[5 + b], most) << "block " << b << "'s passes";
        std::uint32_t next = g.rowsBefore()[from];
        for (std::uint32_t k = 0; k < 4; ++k)
            for (std::uint32_t i = from; i < to; ++i) {
                const shared::PgsElement& e = g.elements()[i];
                if (k >= points(e)) continue;
                EXPECT_EQ(e.normal[k], next++) << "block " << b << ", element " << i << ", point "
                                               << k;
                EXPECT_TRUE(normals.insert(e.normal[k]).second);
                multiPoint += k == 1;
            }
    }
    EXPECT_GE(multiPoint, 8u); // the order differs from the elements' on these
    for (std::uint32_t i = blocks.count; i < g.elements().size(); ++i) {
        const shared::PgsElement& e = g.elements()[i];
        for (std::uint32_t k = 0; k < points(e); ++k) {
            EXPECT_EQ(e.normal[k], g.rowsBefore()[i] + k);
            EXPECT_TRUE(normals.insert(e.normal[k]).second);
        }
    }
    EXPECT_EQ(normals.size(), g.rowCount());
}

// A crate spinning onto the floor (four points apart by 1 - 17 mm) under one falling 10 cm
// above it (a point apart by 104 mm that its spinning corner closes on within the step: from the
// second sweep on that row takes an impulse). In one block the device sweeps the normal rows in
// the CPU's order (every pair's first point, then every second point, ...; its friction rows
// then go element by element, the CPU's by point), and after a step it is within 5e-5 m/s of
// the CPU; colored, the falling crate's row meets the spinning one after all of its floor rows,
// not between them, and the two part by more than 1e-4 m/s.
TEST_F(PgsTwin, OneBlockSweepsTheRowsInTheCpuOrder) {
    const std::string json = cratesOnTheFloor(0.5f, R"(
        {"name": "spin", "shape": "crate", "mass": 1,
         "position": [4.1812286, 0.50881904, 7.8187733],
         "orientation": [0.99986434, -0.0074397363, 0.0146920215, -0.00031289086],
         "linear_velocity": [-1.1263283, -3.1428432, 1.1263282],
         "angular_velocity": [2.7548244, 0.121502586, 2.5118194]},
        {"name": "fall", "shape": "crate", "mass": 1, "position": [4.200001, 1.6712749, 7.800001],
         "orientation": [0.9987707, -0.03938799, -0.0064735194, -0.029390443],
         "linear_velocity": [0, -5.3954997, 0]})");
    World cpu = world(json, Backend::Cpu), oneBlock = world(json, Backend::OpenCl, 1);
    World colored = world(json, Backend::OpenCl, 0);
    ASSERT_TRUE(cpu.step().ok());
    ASSERT_TRUE(oneBlock.step().ok());
    ASSERT_TRUE(colored.step().ok());
    auto apart = [&](const World& w) {
        float worst = 0.0f;
        for (std::uint32_t i = 1; i < cpu.bodyCount(); ++i) {
            const BodyState x = cpu.body(i), y = w.body(i);
            worst = std::max({worst, glm::length(x.linearVelocity - y.linearVelocity),
                              glm::length(x.angularVelocity - y.angularVelocity)});
        }
        return worst;
    };
    // After one step only: from the next on the falling crate strikes, and the two paths part
    // whatever the order.
    std::printf("[ sweep order ] velocity difference from the CPU after one step: one block "
                "%.3g m/s, colored %.3g m/s\n",
                apart(oneBlock), apart(colored));
    EXPECT_LT(apart(oneBlock), 5e-5f);
    EXPECT_GT(apart(colored), 1e-4f);
}

// A stack of three frictionless crates sunk 2 - 3 cm into each other and the floor, each turned a
// little: the split position pass pushes them out over the first steps. In one block the device
// sweeps the push rows in the CPU's order (every pair's first point, then every second, ...,
// as its normal rows) and stays with the CPU to rounding while the crates rise and settle;
// colored, the push rows go element by element, the crates rise on other tilts and the two part
// by more than 0.1 mm in the first step.
TEST_F(PgsTwin, OneBlockPushesInTheCpuOrder) {
    const std::string json = cratesOnTheFloor(0.0f, R"(
        {"name": "s0", "shape": "crate", "mass": 2, "position": [0, 0.48, 0],
         "orientation": [0.9999, 0.01, 0, 0.005]},
        {"name": "s1", "shape": "crate", "mass": 2, "position": [0.05, 1.45, 0],
         "orientation": [0.9998, 0, 0.02, 0.01]},
        {"name": "s2", "shape": "crate", "mass": 2, "position": [-0.04, 2.42, 0.03],
         "orientation": [0.9999, -0.01, 0, 0.008]})");
    World cpu = world(json, Backend::Cpu), oneBlock = world(json, Backend::OpenCl, 1);
    World colored = world(json, Backend::OpenCl, 0);
    // The largest difference of any position or orientation component from the CPU's.
    auto apart = [&](const World& w) {
        float worst = 0.0f;
        for (std::uint32_t i = 1; i < cpu.bodyCount(); ++i) {
            const BodyState x = cpu.body(i), y = w.body(i);
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, std::abs(x.position[k] - y.position[k]));
            for (int k = 0; k < 4; ++k)
                worst = std::max(worst, std::abs(x.orientation[k] - y.orientation[k]));
        }
        return worst;
    };
    const float rise = cpu.body(1).position.y;
    float worstBlock = 0.0f, firstColored = 0.0f;
    for (int step = 1; step <= 60; ++step) {
        ASSERT_TRUE(cpu.step().ok());
        ASSERT_TRUE(oneBlock.step().ok());
        ASSERT_TRUE(colored.step().ok());
        worstBlock = std::max(worstBlock, apart(oneBlock));
        if (step == 1) firstColored = apart(colored);
    }
    std::printf("[ push order ] largest pose difference from the CPU: one block %.3g over 60 "
                "steps, colored %.3g after one\n",
                worstBlock, firstColored);
    EXPECT_GT(cpu.body(1).position.y - rise, 0.01f); // the pass did push the stack out
    EXPECT_LT(worstBlock, 1e-6f);
    EXPECT_GT(firstColored, 1e-4f);
}

// The largest distance between the two ends of any joint of the world, m.
float largestJointError(const World& w, const std::vector<std::array<glm::vec3, 2>>& anchors) {
    float worst = 0.0f;
    const std::span<const JointDesc> joints = w.joints();
    for (std::size_t j = 0; j < joints.size(); ++j) {
        const BodyState a = w.body(joints[j].a), b = w.body(joints[j].b);
        const glm::vec3 pa = a.position + a.orientation * anchors[j][0];
        const glm::vec3 pb = b.position + b.orientation * anchors[j][1];
        worst = std::max(worst, glm::length(pa - pb));
    }
    return worst;
}

// Each joint's anchor in its two bodies' frames, at the world's current poses.
std::vector<std::array<glm::vec3, 2>> jointAnchors(const World& w) {
    std::vector<std::array<glm::vec3, 2>> out;
    for (const JointDesc& j : w.joints()) {
        const BodyState a = w.body(j.a), b = w.body(j.b);
        out.push_back({glm::inverse(a.orientation) * (j.anchor - a.position),
                       glm::inverse(b.orientation) * (j.anchor - b.position)});
    }
    return out;
}

std::uint32_t asleepBodies(const World& w) {
    std::uint32_t n = 0;
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) n += w.body(i).asleep ? 1 : 0;
    return n;
}

std::uint64_t launches(const World& w, const std::string& kernel) {
    return test::deviceProfileByName(w)[kernel].launches;
}

// scenes/pyramid_20.json and stack_10.json stand on the device and fall asleep: after 10 s no
// crate's lowest corner deeper in the floor than the 5 mm slop and a millimetre, all asleep,
// every crate near where it started; then a second more builds no rows and sweeps nothing (a
// pile asleep costs no solve). Near: within 5 cm in the CPU's order (one block) and within 6 cm
// in the orders that are not the CPU's (a pile that falls moves metres). Colored, a sweep takes
// each pair's points both ways and its normal rows twice (kernels/pgs_sweep.cl, solveElement): taken
// first to last only, the piles would lean toward the corner of their manifolds' first points.
TEST_F(PgsTwin, PyramidAndStackStandAndSleepOnTheDevice) {
    // As the device suits (PoCL's CPU device: one block for worlds this small, the CPU's order),
    // in the eight blocks a large world gets here (the elements between them colored) and
    // colored (as a GPU would).
    for (const auto& [name, blocks] : {std::pair{"pyramid_20.json", -1},
                                       {"stack_10.json", -1},
                                       {"pyramid_20.json", 8},
                                       {"stack_10.json", 8},
                                       {"pyramid_20.json", 0},
                                       {"stack_10.json", 0}}) {
        World w = sceneFile(name, Backend::OpenCl, blocks);
        const std::vector<glm::vec3> start = test::positionsOf(w);
        for (int step = 0; step < 600; ++step) ASSERT_TRUE(w.step().ok()) << name;
        float moved = 0.0f;
        std::uint32_t dynamic = 0;
        for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
            if (w.body(i).isStatic) continue;
            ++dynamic;
            moved = std::max(moved, glm::length(w.body(i).position - start[i]));
        }
        const test::FloorReach sunk = test::deepestBelowFloor(w);
        std::printf("[ %s, blocks %d ] largest displacement %.4f m, %u of %u asleep, deepest "
                    "corner %.4f m below the floor\n",
                    name, blocks, moved, asleepBodies(w), dynamic, sunk.depth);
        EXPECT_LT(moved, blocks < 0 ? 0.05f : 0.06f) << name;
        EXPECT_LT(sunk.depth, 0.006) << name << ": " << sunk.name << "'s lowest corner, m";
        EXPECT_EQ(asleepBodies(w), dynamic) << name;
        const std::uint64_t built = launches(w, "buildPgsRows"), swept = launches(w, "solvePgs");
        EXPECT_GT(built, 0u) << name;
        for (int step = 0; step < 60; ++step) ASSERT_TRUE(w.step().ok()) << name;
        EXPECT_EQ(launches(w, "buildPgsRows"), built) << name;
        EXPECT_EQ(launches(w, "solvePgs"), swept) << name;
    }
}

// A world below 2 x kPgsBlockBodies bodies runs as one block on a CPU device, whose sweeps take
// every row in the CPU's order (normal, friction and push rows and the warm start by point),
// and sleeps by the CPU's islands: pyramid_20, 210 crates and 1,600 contact points,
// steps the CPU's bits on the device, every body at every step, through the crates falling
// asleep (from step 30) until the whole pile sleeps, and on. Each body sleeping by itself on
// the device, or the friction rows and the warm start taken element by element (as eight blocks
// take them), would part from the CPU within these steps.
TEST_F(PgsTwin, ASmallWorldStepsTheCpuBitForBitThroughSleep) {
    World cpu = sceneFile("pyramid_20.json", Backend::Cpu);
    World device = sceneFile("pyramid_20.json", Backend::OpenCl);
    std::uint32_t contacts = 0;
    for (int step = 1; step <= 90; ++step) {
        ASSERT_TRUE(cpu.step().ok()) << "step " << step;
        ASSERT_TRUE(device.step().ok()) << "step " << step;
        ASSERT_EQ(device.lastStep().contactCount, cpu.lastStep().contactCount) << "step " << step;
        ASSERT_EQ(device.lastStep().asleep, cpu.lastStep().asleep) << "step " << step;
        contacts = std::max(contacts, cpu.lastStep().contactCount);
        for (std::uint32_t i = 0; i < cpu.bodyCount(); ++i) {
            ASSERT_TRUE(test::sameBits(cpu.body(i), device.body(i)))
                << cpu.bodyName(i) << " at step " << step;
            ASSERT_EQ(device.body(i).asleep, cpu.body(i).asleep)
                << cpu.bodyName(i) << " at step " << step;
        }
    }
    EXPECT_GE(contacts, 1000u); // the pile's contacts, not a free fall
    EXPECT_EQ(asleepBodies(device), cpu.bodyCount() - 1) << "the whole pile asleep";
}

// A world at rest is left alone: once every body of pyramid_20 sleeps and a step has found no
// pair, the device's steps are left out (World's stepDevice, Pipeline::atRest: no launch, no
// wait) until an explosion at 2 s wakes the pile, which then moves as on the CPU to the bit,
// its warm start and sleep included; at rest again, an impulse from the host makes the device
// step again, and the pile follows the CPU's to the bit.
TEST_F(PgsTwin, AWorldAtRestIsLeftOutUntilAnExplosionWakesIt) {
    Result<Scene> scene = loadScene(std::string(RUBBLE_SOURCE_DIR) + "/scenes/pyramid_20.json");
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    EventDesc boom;
    boom.where = "test";
    boom.time = 2.0f;
    boom.centre = glm::vec3(0.3f, 0.2f, 0.1f);
    boom.impulse = 4.0f;
    boom.radius = 6.0f;
    scene->events.push_back(boom);
    World cpu = world(*scene, Backend::Cpu);
    World device = world(*scene, Backend::OpenCl);
    int leftOut = 0, leftOutAfterBoom = 0;
    float fastest = 0.0f;
    for (int step = 1; step <= 240; ++step) {
        ASSERT_TRUE(cpu.step().ok()) << "step " << step;
        ASSERT_TRUE(device.step().ok()) << "step " << step;
        const bool boomed = double(step) * double(scene->simulation.dt) > boom.time;
        // No wait for the device: the step was not enqueued.
        if (device.lastStep().deviceWaitMs == 0.0) {
            ++leftOut;
            if (boomed) ++leftOutAfterBoom;
            ASSERT_EQ(asleepBodies(device), device.bodyCount() - 1) << "step " << step;
        }
        ASSERT_EQ(device.lastStep().contactCount, cpu.lastStep().contactCount) << "step " << step;
        ASSERT_EQ(device.lastStep().asleep, cpu.lastStep().asleep) << "step " << step;
        for (std::uint32_t i = 0; i < cpu.bodyCount(); ++i) {
            ASSERT_TRUE(test::sameBits(cpu.body(i), device.body(i)))
                << cpu.bodyName(i) << " at step " << step;
            if (boomed) fastest = std::max(fastest, glm::length(device.body(i).linearVelocity));
        }
    }
    std::printf("[ pyramid_20 at rest ] %d of 240 steps left out, %d after the explosion\n",
                leftOut, leftOutAfterBoom);
    EXPECT_GE(leftOut, 20) << "steps at rest left out before the explosion";
    EXPECT_GT(fastest, 1.0f) << "m/s: the explosion woke the pile";
    EXPECT_GE(leftOutAfterBoom, 1) << "the pile came back to rest";
    // At rest again, an impulse from the host (World::applyImpulse) goes up and the device steps.
    const std::uint32_t top = cpu.bodyCount() - 1;
    const glm::vec3 at = cpu.body(top).position;
    cpu.applyImpulse(top, glm::vec3(3.0f, 0.0f, 0.0f), at);
    device.applyImpulse(top, glm::vec3(3.0f, 0.0f, 0.0f), at);
    for (int step = 1; step <= 30; ++step) {
        ASSERT_TRUE(cpu.step().ok()) << "step " << step << " after the impulse";
        ASSERT_TRUE(device.step().ok()) << "step " << step << " after the impulse";
        if (step == 1) {
            EXPECT_GT(device.lastStep().deviceWaitMs, 0.0) << "the step ran";
        }
        // The woken pairs run the whole SAT on both (no features from a carried pair): the
        // same manifolds, the same bits.
        for (std::uint32_t i = 0; i < cpu.bodyCount(); ++i)
            ASSERT_TRUE(test::sameBits(cpu.body(i), device.body(i)))
                << cpu.bodyName(i) << " at step " << step << " after the impulse";
    }
    EXPECT_GT(glm::distance(device.body(top).position, at), 0.05f) << "m: the top crate moved";
}

// Every block takes its friction rows and warm start by point, as one block does: two stacks in
// two blocks, no element between them, step the CPU's bits, every body every step.
TEST_F(PgsTwin, BlocksByPointStepTheCpuBitForBit) {
    // Bodies 1 - 3 and 4 - 6: of seven bodies, two blocks cut at body 4.
    const std::string json = cratesOnTheFloor(0.5f, R"(
      {"name": "a0", "shape": "crate", "mass": 1, "position": [-3, 0.49, 0],
       "linear_velocity": [0.8, 0, 0.3]},
      {"name": "a1", "shape": "crate", "mass": 1, "position": [-2.95, 1.47, 0.04],
       "orientation": [0.9998, 0, 0.02, 0]},
      {"name": "a2", "shape": "crate", "mass": 1, "position": [-3.02, 2.45, -0.03],
       "angular_velocity": [0, 1, 0]},
      {"name": "b0", "shape": "crate", "mass": 1, "position": [3, 0.49, 0],
       "orientation": [0.9999, 0.01, 0, 0]},
      {"name": "b1", "shape": "crate", "mass": 1, "position": [3.05, 1.47, 0],
       "linear_velocity": [-0.6, 0, 0.5]},
      {"name": "b2", "shape": "crate", "mass": 1, "position": [2.97, 2.45, 0.02],
       "orientation": [0.9998, 0.02, 0, 0]})");
    const Scene scene = sceneOf(json);
    World cpu = world(scene, Backend::Cpu);
    World device = world(scene, Backend::OpenCl, 2);
    std::uint32_t contacts = 0;
    for (int step = 1; step <= 60; ++step) {
        ASSERT_TRUE(cpu.step().ok()) << "step " << step;
        ASSERT_TRUE(device.step().ok()) << "step " << step;
        contacts = std::max(contacts, cpu.lastStep().contactCount);
        for (std::uint32_t i = 0; i < cpu.bodyCount(); ++i)
            ASSERT_TRUE(test::sameBits(cpu.body(i), device.body(i)))
                << cpu.bodyName(i) << " at step " << step;
    }
    EXPECT_GE(contacts, 20u) << "two stacks of three on the floor, four points a face";
}

// A column of sixteen leaning over, toppling slowly: on the device as on the CPU
// (Sleep.BaseOfASlowlyTopplingColumnStaysAwake) it is one island with its moving top, so its
// base, slower than the sleep speeds for the first second, stays awake and is dragged along,
// and the device steps the CPU's bits throughout. (Each body sleeping by itself, the base fell
// asleep under the column as a fixed pivot.)
TEST_F(PgsTwin, BaseOfASlowlyTopplingColumnStaysAwakeAsOnTheCpu) {
    World cpu = world(test::leaningColumnScene(), Backend::Cpu);
    World device = world(test::leaningColumnScene(), Backend::OpenCl);
    const float topStart = device.body(16).position.x;
    for (int step = 1; step <= 180; ++step) {
        ASSERT_TRUE(cpu.step().ok()) << "step " << step;
        ASSERT_TRUE(device.step().ok()) << "step " << step;
        for (std::uint32_t i = 1; i < device.bodyCount(); ++i) {
            ASSERT_FALSE(device.body(i).asleep) << device.bodyName(i) << " at step " << step;
            ASSERT_TRUE(test::sameBits(cpu.body(i), device.body(i)))
                << device.bodyName(i) << " at step " << step;
        }
    }
    EXPECT_GT(device.body(16).position.x - topStart, 2.0f) << "m the top has moved: it topples";
    EXPECT_GT(glm::length(device.body(1).linearVelocity), 1e-3f) << "m/s: the base moves with it";
}

// scenes/ragdoll_pile.json with every body on the device: joints hold to a tenth of a
// millimetre through the fall, and at 20 s no body's lowest point is deeper in the floor than
// the 5 mm slop and 3 mm. In the order the device suits (one block, the CPU's order, with the
// joints projected in double and the islands decided on the host, as the CPU does) the pile at
// 20 s is the CPU's to the bit, its sleep too. In every order the pile has settled by 20 s: no
// body faster than 0.1 m/s and at least one doll's island (10 bodies) asleep. Not all of them:
// a head rocking on a corner, or a limb swinging on in an order that is not the CPU's, holds
// its island awake a while longer.
TEST_F(PgsTwin, RagdollPileHoldsItsJointsAndSettlesOnTheDevice) {
    // As the device suits (one block: 161 bodies), in eight blocks (as PoCL's CPU device runs a
    // large world; the joints between blocks go through the colors) and colored (as a GPU would:
    // every joint in a color).
    World cpu = sceneFile("ragdoll_pile.json", Backend::Cpu);
    for (int step = 1; step <= 1200; ++step) ASSERT_TRUE(cpu.step().ok()) << "step " << step;
    float cpuFastest = 0.0f;
    for (std::uint32_t i = 0; i < cpu.bodyCount(); ++i)
        cpuFastest = std::max(cpuFastest, glm::length(cpu.body(i).linearVelocity));
    std::printf("[ ragdoll_pile, CPU ] %u asleep at 20 s, fastest %.3g m/s, deepest %.4f m\n",
                asleepBodies(cpu), cpuFastest, test::deepestBelowFloor(cpu).depth);
    for (const int blocks : {-1, 8, 0}) ragdollPileSettles(blocks, cpu);
}

void PgsTwin::ragdollPileSettles(int blocks, const World& cpu) {
    SCOPED_TRACE("blocks " + std::to_string(blocks));
    World w = sceneFile("ragdoll_pile.json", Backend::OpenCl, blocks);
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
        if (!w.body(i).isStatic) {
            ASSERT_TRUE(w.onDevice(i)) << w.bodyName(i);
        }
    }
    const std::vector<std::array<glm::vec3, 2>> anchors = jointAnchors(w);
    float worst = 0.0f;
    for (int step = 1; step <= 1200; ++step) {
        ASSERT_TRUE(w.step().ok()) << "step " << step;
        if (step % 20 == 0) worst = std::max(worst, largestJointError(w, anchors));
    }
    std::uint32_t dynamic = 0;
    float fastest = 0.0f;
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
        if (w.body(i).isStatic) continue;
        ++dynamic;
        fastest = std::max(fastest, glm::length(w.body(i).linearVelocity));
    }
    const test::FloorReach sunk = test::deepestBelowFloor(w);
    std::printf("[ ragdoll_pile, blocks %d ] largest joint error %.3g m, %u of %u asleep at 20 s, "
                "fastest %.3g m/s, deepest point %.4f m below the floor\n",
                blocks, worst, asleepBodies(w), dynamic, fastest, sunk.depth);
    EXPECT_LT(worst, 1e-4f);
    EXPECT_LT(sunk.depth, 0.008) << sunk.name << "'s lowest point, m";
    EXPECT_LT(fastest, 0.1f) << "m/s";
    EXPECT_GE(asleepBodies(w), 10u) << "bodies asleep at 20 s";
    if (blocks >= 0) return;
    EXPECT_EQ(asleepBodies(w), asleepBodies(cpu));
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i)
        EXPECT_TRUE(test::sameBits(cpu.body(i), w.body(i))) << w.bodyName(i);
}

// scenes/explosion.json with every body on the device (the debris set, the ragdoll, the door,
// the chain and the seesaw): through the blast at 0.5 s and 1.5 s after it, no body reaches
// 2 cm into the floor (pieces still land at speed) and the joints hold to 3e-5 m on the device
// as on the CPU, each group projected as one on both (joint by joint, 20 sweeps would leave the
// chain millimetres apart).
TEST_F(PgsTwin, ExplosionRunsWithEveryBodyOnTheDevice) {
    World w = sceneFile("explosion.json", Backend::OpenCl);
    World cpu = sceneFile("explosion.json", Backend::Cpu);
    std::uint32_t dynamic = 0;
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
        if (w.body(i).isStatic) continue;
        ++dynamic;
        ASSERT_TRUE(w.onDevice(i)) << w.bodyName(i);
    }
    const std::vector<std::array<glm::vec3, 2>> anchors = jointAnchors(w);
    ASSERT_FALSE(anchors.empty());
    float worst = 0.0f, worstCpu = 0.0f;
    for (int step = 1; step <= 120; ++step) {
        ASSERT_TRUE(w.step().ok()) << "step " << step;
        ASSERT_TRUE(cpu.step().ok()) << "step " << step;
        if (step % 10 != 0) continue;
        worst = std::max(worst, largestJointError(w, anchors));
        worstCpu = std::max(worstCpu, largestJointError(cpu, anchors));
    }
    const test::FloorReach sunk = test::deepestBelowFloor(w),
                           sunkCpu = test::deepestBelowFloor(cpu);
    std::printf("[ explosion ] %u bodies on the device, largest joint error %.3g m (CPU %.3g m), "
                "deepest point %.4f m below the floor (CPU %.4f m)\n",
                dynamic, worst, worstCpu, sunk.depth, sunkCpu.depth);
    EXPECT_LT(worst, 3e-5f) << "m, on the device";
    EXPECT_LT(worstCpu, 3e-5f) << "m, on the CPU";
    EXPECT_LT(sunk.depth, 0.02) << sunk.name << "'s lowest point, m, on the device";
    EXPECT_LT(sunkCpu.depth, 0.02) << sunkCpu.name << "'s lowest point, m, on the CPU";
}

} // namespace
} // namespace rubble
