// tests/gpu/device_physics_test.cpp: whole runs on the OpenCL backend (particles and Jacobi): a
// pile comes to rest, a stack stands, a concave mesh holds a box in its hollow; the device run
// equals its CPU twin in deterministic mode and repeats bit for bit; the SAT path's steps do
// not depend on how a launch's items are split among its work-items.
#include <cstring>
#include <vector>

#include "gpu_fixture.h"
#include "support/floor_reach.h"

namespace rubble {
namespace {

class DevicePhysics : public test::GpuTest {};

std::string boxes(const std::string& generator, float spacing, const std::string& extra = "") {
    return R"({"format": "rubble-scene", "version": 1, "name": "boxes",
      "simulation": {"dt": 0.016666667, "collision": {"method": "particles",
                     "particle_spacing": )" + std::to_string(spacing) + R"(},
                     "solver": {"type": "jacobi", "iterations": 10}},
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true})" + extra + R"(],
      "generators": [)" + generator + "]}";
}

float maxSpeed(const World& w) {
    float v = 0.0f;
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i)
        v = std::max(v, glm::length(w.body(i).linearVelocity));
    return v;
}

// 256 unit boxes dropped in a jittered 16 x 2 x 8 block: after 8 s every one is asleep and no
// box's lowest particle is deeper in the floor than the particle contacts' slop allows.
TEST_F(DevicePhysics, APileOf256BoxesComesToRest) {
    World w = deviceWorld(boxes(R"({"type": "grid", "shape": "crate", "mass": 1,
        "count": [16, 2, 8], "origin": [-8.5, 1.0, -4.2], "spacing": [1.1, 1.1, 1.1],
        "rotation_jitter": 0.1, "seed": 1, "name_prefix": "d"})", 0.5f));
    for (int i = 0; i < 480; ++i) ASSERT_TRUE(w.step().ok()) << "step " << i;
    // At rest: every box asleep, so still to the bit.
    EXPECT_EQ(maxSpeed(w), 0.0f);
    for (std::uint32_t i = 1; i < w.bodyCount(); ++i) {
        EXPECT_TRUE(w.body(i).asleep) << w.bodyName(i);
        EXPECT_EQ(glm::length(w.body(i).angularVelocity), 0.0f) << w.bodyName(i);
    }
    // 2 x 2 x 2 particles of radius 0.25 m stand for each box; the Jacobi rows leave up to a
    // tenth of the spacing of a resting contact's penetration uncorrected (particleSlopItem).
    const test::FloorReach sunk = test::deepestBelowFloor(w, 0.25);
    EXPECT_LT(sunk.depth, 0.05) << "m, " << sunk.name << "'s lowest particle below the floor";
}

// A stack of three unit boxes on the floor, with `simulation` as given.
std::string stackOfThree(const std::string& simulation) {
    return R"({"format": "rubble-scene", "version": 1, "simulation": {)" + simulation + R"(},
      "shapes": {"floor": {"type": "plane"}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true},
                 {"name": "b0", "shape": "crate", "mass": 1, "position": [0, 0.5, 0]},
                 {"name": "b1", "shape": "crate", "mass": 1, "position": [0, 1.5, 0]},
                 {"name": "b2", "shape": "crate", "mass": 1, "position": [0, 2.5, 0]}]})";
}

// simulation.sleep on each of the device's sleep paths (SAT by the host's islands, SAT with
// each body by itself, particles with Jacobi): with true the settled stack is asleep after 4 s,
// with false no box is, and the stack stands as it does asleep.
TEST_F(DevicePhysics, SleepFalseKeepsEverySettledBodyAwake) {
    const std::string sat = R"("collision": {"method": "sat"})";
    const std::string particles =
        R"("collision": {"method": "particles", "particle_spacing": 0.25}, "solver": {"type": "jacobi"})";
    struct Path {
        const char* name;
        std::string simulation;
        bool bodySleep;
    };
    for (const Path& path : {Path{"sat, islands", sat, false}, Path{"sat, body sleep", sat, true},
                             Path{"particles, jacobi", particles, false}}) {
        for (const bool sleep : {true, false}) {
            SCOPED_TRACE(std::string(path.name) + (sleep ? ", sleep true" : ", sleep false"));
            RunOptions run;
            run.bodySleep = path.bodySleep;
            World w = deviceWorld(
                stackOfThree(path.simulation + R"(, "sleep": )" + (sleep ? "true" : "false")), run);
            ASSERT_TRUE(test::stepWorld(w, 240));
            for (std::uint32_t i = 1; i <= 3; ++i) {
                EXPECT_EQ(w.body(i).asleep, sleep) << w.bodyName(i);
                EXPECT_NEAR(w.body(i).position.x, 0.0f, 0.02f) << w.bodyName(i);
                EXPECT_NEAR(w.body(i).position.y, float(i) - 0.5f, 0.05f) << w.bodyName(i);
            }
            EXPECT_EQ(w.lastStep().asleep, sleep ? 3u : 0u);
            if (!sleep) {
                EXPECT_GT(w.lastStep().contactCount, 0u) << "awake: collided every step";
            }
        }
    }
}

// Five unit boxes on each other stand for 10 s: the top one stays within 5 cm of where it was.
TEST_F(DevicePhysics, AStackOfFiveStands) {
    World w = deviceWorld(boxes(R"({"type": "grid", "shape": "crate", "mass": 1,
        "count": [1, 5, 1], "origin": [0, 0.5, 0], "spacing": [1, 1, 1], "name_prefix": "s"})",
                                0.25f));
    const glm::vec3 top0 = w.body(5).position;
    for (int i = 0; i < 600; ++i) ASSERT_TRUE(w.step().ok());
    const glm::vec3 top = w.body(5).position;
    EXPECT_NEAR(top.x, top0.x, 0.05f);
    EXPECT_NEAR(top.z, top0.z, 0.05f);
    EXPECT_NEAR(top.y, top0.y, 0.05f);
    EXPECT_LT(maxSpeed(w), 0.05f);
}

// An L-shaped prism, 1.5 m x 1.5 m with 0.5 m arms, 0.5 m deep, as OBJ triangles wound
// outward: its centre of mass is (0.55, 0.55, 0.25) from the outer corner.
std::string lBlockObj() {
    const float p[6][2] = {{0, 0}, {1.5f, 0}, {1.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 1.5f}, {0, 1.5f}};
    std::string obj;
    for (int z = 0; z < 2; ++z)
        for (const auto& v : p)
            obj += "v " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
                   std::to_string(0.5f * float(z)) + "\n";
    auto face = [&](int a, int b, int c) {
        obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
    };
    // The L as a fan from its outer corner (every fan triangle lies inside it), front and back.
    for (int k = 1; k < 5; ++k) {
        face(7, 7 + k, 8 + k);
        face(1, 2 + k, 1 + k);
    }
    for (int i = 0; i < 6; ++i) {
        const int j = (i + 1) % 6;
        face(1 + i, 1 + j, 7 + j);
        face(1 + i, 7 + j, 7 + i);
    }
    return obj;
}

// The L lies on the floor; a small box dropped over its inner corner lands on the real surface
// of the short arm (top 0.5 m up), not on the hull's slope, which is 1 m up there.
TEST_F(DevicePhysics, AConcaveMeshHoldsABoxInItsHollow) {
    const std::string dir = test::tempDir("l_block");
    test::writeText(dir + "/l_block.obj", lBlockObj());
    const std::string scene = R"({"format": "rubble-scene", "version": 1, "name": "l",
      "simulation": {"dt": 0.016666667, "collision": {"method": "particles",
                     "particle_spacing": 0.125}, "solver": {"type": "jacobi"}},
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "l": {"type": "mesh", "file": ")" + dir + R"(/l_block.obj"},
                 "cube": {"type": "box", "half_extents": [0.2, 0.2, 0.2]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true},
                 {"name": "l", "shape": "l", "mass": 10, "position": [0.55, 0.57, 0.25]},
                 {"name": "cube", "shape": "cube", "mass": 0.5, "position": [1.0, 1.6, 0.25]}]})";
    World w = deviceWorld(scene);
    for (int i = 0; i < 240; ++i) ASSERT_TRUE(w.step().ok());
    const BodyState l = w.body(1), cube = w.body(2);
    // The L rests on its long side: its centre of mass 0.55 m up.
    EXPECT_NEAR(l.position.y, 0.55f, 0.05f);
    // The cube sits in the corner: its centre 0.2 m above the short arm's top.
    EXPECT_LT(cube.position.y, 0.85f);
    EXPECT_GT(cube.position.y, 0.55f);
    EXPECT_LT(maxSpeed(w), 0.1f);
}

std::string debris() {
    return std::string(RUBBLE_SOURCE_DIR) + "/scenes/bench/debris_1k.json";
}

Scene debrisScene() {
    Result<Scene> scene = loadScene(debris());
    EXPECT_TRUE(scene.ok());
    scene->simulation.collision.method = CollisionMethod::Particles;
    scene->simulation.collision.particleSpacing = 0.5f;
    scene->simulation.solver.type = SolverType::Jacobi;
    return *scene;
}

// The 1,024-box debris scene for 60 steps, particles and Jacobi: the device in deterministic
// mode and the CPU twin add the same numbers in the same order, so they agree to 1e-5 m (they
// are in fact equal on PoCL); the device's sin/sqrt may differ from the host's elsewhere.
TEST_F(DevicePhysics, DebrisOnTheDeviceMatchesTheCpuTwin) {
    Scene scene = debrisScene();
    Result<World> cpu = World::create(scene);
    ASSERT_TRUE(cpu.ok()) << cpu.error().describe();
    scene.simulation.backend = Backend::OpenCl;
    RunOptions run;
    run.context = context();
    run.deterministic = true;
    Result<World> gpuWorld = World::create(scene, run);
    ASSERT_TRUE(gpuWorld.ok()) << gpuWorld.error().describe();
    for (int i = 0; i < 60; ++i) {
        ASSERT_TRUE(cpu->step().ok());
        ASSERT_TRUE(gpuWorld->step().ok());
    }
    EXPECT_GT(gpuWorld->lastStep().contactCount, 300u);
    EXPECT_EQ(gpuWorld->lastStep().contactCount, cpu->lastStep().contactCount);
    float worst = 0.0f;
    for (std::uint32_t i = 0; i < cpu->bodyCount(); ++i)
        worst = std::max(worst, glm::length(cpu->body(i).position - gpuWorld->body(i).position));
    EXPECT_LT(worst, 1e-5f);
}

// Deterministic mode: two device runs of the same scene are equal to the last bit.
TEST_F(DevicePhysics, DeterministicRunsRepeatBitForBit) {
    std::vector<std::vector<BodyState>> runs;
    for (int r = 0; r < 2; ++r) {
        Scene scene = debrisScene();
        scene.simulation.backend = Backend::OpenCl;
        RunOptions run;
        run.context = context();
        run.deterministic = true;
        Result<World> w = World::create(scene, run);
        ASSERT_TRUE(w.ok()) << w.error().describe();
        for (int i = 0; i < 60; ++i) ASSERT_TRUE(w->step().ok());
        runs.emplace_back();
        for (std::uint32_t i = 0; i < w->bodyCount(); ++i) runs.back().push_back(w->body(i));
    }
    for (std::size_t i = 0; i < runs[0].size(); ++i) {
        EXPECT_EQ(std::memcmp(&runs[0][i].position, &runs[1][i].position, sizeof(glm::vec3)), 0);
        EXPECT_EQ(std::memcmp(&runs[0][i].orientation, &runs[1][i].orientation,
                              sizeof(glm::quat)), 0);
    }
}

// The kernels that go through the step's pairs split them among their work-items in runs of
// consecutive pairs on a CPU device and one group-width apart on a GPU (RUBBLE_CONTIGUOUS_ITEMS).
// 4,624 crates on the floor, a few turned, some pressed into their neighbours: more floor pairs
// than the launch has work-items (4,096 on two compute units), so that each work-item takes
// several. Built the GPU's way on this device, three steps of SAT and PGS give the same bodies
// to the last bit as this device's own way.
TEST_F(DevicePhysics, TheSplitOfALaunchsPairsAmongItsWorkItemsChangesNoBit) {
    const std::string json = R"({"format": "rubble-scene", "version": 1, "name": "floor pairs",
      "simulation": {"dt": 0.016666667, "backend": "opencl", "collision": {"method": "sat"},
                     "solver": {"type": "pgs", "iterations": 10}},
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [68, 1, 68],
                      "origin": [0, 0.49, 0], "spacing": [0.99, 1, 1.2],
                      "rotation_jitter": 0.05, "seed": 3}]})";
    Result<Scene> scene = parseScene(json, "floor_pairs.json", ".");
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    ASSERT_TRUE(context()->workSizes().contiguousItems) << "PoCL is a CPU device";
    // Added after the work sizes' -DRUBBLE_CONTIGUOUS_ITEMS=1, this definition wins (the
    // compiler warns of the redefinition).
    RunOptions gpuWay;
    gpuWay.buildOptions = "-DRUBBLE_CONTIGUOUS_ITEMS=0";
    Result<std::shared_ptr<gpu::Context>> strided = openDevice(gpuWay);
    ASSERT_TRUE(strided.ok()) << strided.error().describe();
    std::vector<std::vector<BodyState>> runs;
    for (const std::shared_ptr<gpu::Context>& c : {context(), *strided}) {
        RunOptions run;
        run.context = c;
        Result<World> w = World::create(*scene, run);
        ASSERT_TRUE(w.ok()) << w.error().describe();
        for (int i = 0; i < 3; ++i) ASSERT_TRUE(w->step().ok());
        // Every crate on the floor, most of them against their neighbours too.
        EXPECT_GT(w->lastStep().contactCount, 4u * 4624u);
        runs.emplace_back();
        for (std::uint32_t i = 0; i < w->bodyCount(); ++i) runs.back().push_back(w->body(i));
    }
    std::size_t differ = 0;
    for (std::size_t i = 0; i < runs[0].size(); ++i) {
        differ += std::memcmp(&runs[0][i].position, &runs[1][i].position, sizeof(glm::vec3)) != 0 ||
                  std::memcmp(&runs[0][i].orientation, &runs[1][i].orientation,
                              sizeof(glm::quat)) != 0 ||
                  std::memcmp(&runs[0][i].linearVelocity, &runs[1][i].linearVelocity,
                              sizeof(glm::vec3)) != 0;
    }
    EXPECT_EQ(differ, 0u);
}

} // namespace
} // namespace rubble
