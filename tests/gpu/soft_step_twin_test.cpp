// tests/gpu/soft_step_twin_test.cpp: the soft step on the device (host/gpu/soft_step.cpp)
// against the CPU reference (SoftStepSolver): a block in the CPU's order steps the CPU's bits
// (contacts, friction, restitution, ball and hinge joints), and the colored path keeps a stack
// of ten standing and brings a wall of twenty rows to rest.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gpu_fixture.h"

namespace rubble {
namespace {

class SoftStepTwin : public test::GpuTest {
  protected:
    // A world of `scene` with SAT and the soft step, on the CPU or on the device with `blocks`
    // (RunOptions::pgsBlocks: 0 every element colored).
    World world(const Scene& scene, Backend backend, int blocks = -1) {
        return worldOf(scene, backend, CollisionMethod::Sat, SolverType::SoftStep, blocks);
    }
    // Steps both worlds `steps` times; every body's state the same bits after each step.
    void expectSameBits(World& cpu, World& device, int steps) {
        for (int step = 1; step <= steps; ++step) {
            ASSERT_TRUE(cpu.step().ok()) << "step " << step;
            ASSERT_TRUE(device.step().ok()) << "step " << step;
            ASSERT_EQ(device.lastStep().contactCount, cpu.lastStep().contactCount)
                << "step " << step;
            for (std::uint32_t i = 0; i < cpu.bodyCount(); ++i)
                ASSERT_TRUE(test::sameBits(cpu.body(i), device.body(i)))
                    << cpu.bodyName(i) << " at step " << step << ": cpu y "
                    << cpu.body(i).position.y << ", device y " << device.body(i).position.y;
        }
    }
};

// Unit crates on a floor at 60 Hz with the soft step's defaults; `bodies` follow the floor.
std::string crates(const std::string& bodies, const std::string& joints = "") {
    return R"({"format": "rubble-scene", "version": 1, "name": "soft",
      "simulation": {"dt": 0.016666667, "solver": {"type": "soft-step"}},
      "materials": {"default": {"friction": 0.5, "restitution": 0.0},
                    "bouncy": {"friction": 0.6, "restitution": 0.7}},
      "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "ball": {"type": "sphere", "radius": 0.3},
                 "link": {"type": "box", "half_extents": [0.05, 0.3, 0.05]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},)" +
           bodies + "]" + (joints.empty() ? "" : R"(, "joints": [)" + joints + "]") + "}";
}

// A crate on the floor, a stack of three a little into each other (the springs push out), a
// crate sliding at 2 m/s (friction), a bouncy ball landing at 4 m/s (restitution after the
// substeps): one block goes through the rows in the CPU's order, so every step is the CPU's to
// the bit.
TEST_F(SoftStepTwin, OneBlockStepsTheCpuBitForBit) {
    const Scene scene = sceneOf(crates(R"(
      {"name": "rest", "shape": "crate", "mass": 1, "position": [-4, 0.5, 0]},
      {"name": "s0", "shape": "crate", "mass": 2, "position": [0, 0.49, 0]},
      {"name": "s1", "shape": "crate", "mass": 2, "position": [0.05, 1.47, 0],
       "orientation": [0.9998, 0, 0.02, 0]},
      {"name": "s2", "shape": "crate", "mass": 2, "position": [-0.04, 2.45, 0.03]},
      {"name": "slide", "shape": "crate", "mass": 3, "position": [4, 0.499, 0],
       "linear_velocity": [2, 0, 0.5]},
      {"name": "ball", "shape": "ball", "material": "bouncy", "mass": 1,
       "position": [0, 0.295, 4], "linear_velocity": [0, -4, 0]})"));
    World cpu = world(scene, Backend::Cpu);
    World device = world(scene, Backend::OpenCl, 1);
    expectSameBits(cpu, device, 60);
    // The stack stands and the slider has stopped on both: the scene exercised the contacts.
    EXPECT_NEAR(device.body(4).position.y, 2.45, 0.05);
    EXPECT_LT(std::abs(device.body(5).linearVelocity.x), 0.05);
}

// A pendulum on a ball joint and a door on a hinge, swinging: the soft joint blocks at each
// substep's poses are the CPU's to the bit.
TEST_F(SoftStepTwin, JointsStepTheCpuBitForBit) {
    const Scene scene = sceneOf(crates(R"(
      {"name": "pivot", "shape": "link", "static": true, "position": [0, 3, 0]},
      {"name": "bob", "shape": "link", "mass": 1, "position": [0.3, 2.7, 0],
       "orientation": [0.9239, 0, 0, 0.3827]},
      {"name": "frame", "shape": "link", "static": true, "position": [3, 1, 0]},
      {"name": "door", "shape": "crate", "mass": 5, "position": [3.6, 1, 0],
       "angular_velocity": [0, 2, 0]})",
                                       R"(
      {"type": "ball", "a": "pivot", "b": "bob", "anchor": [0, 3, 0]},
      {"type": "hinge", "a": "frame", "b": "door", "anchor": [3, 1, 0], "axis": [0, 1, 0]})"));
    World cpu = world(scene, Backend::Cpu);
    World device = world(scene, Backend::OpenCl, 1);
    expectSameBits(cpu, device, 60);
    // The bob has swung on its joint, its centre at its start's distance from the pivot
    // (0.3 sqrt 2 m) within the spring's give.
    const BodyState bob = device.body(2);
    EXPECT_NEAR(glm::length(bob.position - glm::vec3(0, 3, 0)), 0.3 * std::sqrt(2.0), 0.01);
    EXPECT_GT(glm::length(bob.position - glm::vec3(0.3f, 2.7f, 0)), 0.05) << "it swings";
}

// Two stacks of three, cut into two blocks at body 4 (of seven): each block in the CPU's
// order, the blocks sharing no moving body, so the world is the CPU's to the bit.
TEST_F(SoftStepTwin, TwoBlocksStepTheCpuBitForBit) {
    const Scene scene = sceneOf(crates(R"(
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
      {"name": "b2", "shape": "crate", "mass": 1, "position": [2.97, 2.45, 0.02]})"));
    World cpu = world(scene, Backend::Cpu);
    World device = world(scene, Backend::OpenCl, 2);
    expectSameBits(cpu, device, 60);
}

// The colored path (a GPU's: every element colored, one launch per color and pass) keeps a
// stack of ten standing, awake throughout: after 300 steps its top has moved less than 2 cm
// sideways and sits where the springs' overlaps put it (ten contacts under the load above each,
// about 2.6 cm in all at 30 Hz), within 1 cm of the CPU's.
TEST_F(SoftStepTwin, ColoredStackOfTenStands) {
    std::string boxes;
    for (int i = 0; i < 10; ++i)
        boxes += std::string(i ? "," : "") + R"({"name": "box)" + std::to_string(i) +
                 R"(", "shape": "crate", "mass": 1, "position": [0, )" + std::to_string(0.5 + i) +
                 ", 0]}";
    Scene scene = sceneOf(crates(boxes));
    scene.simulation.sleep = false;
    World cpu = world(scene, Backend::Cpu);
    World device = world(scene, Backend::OpenCl, 0);
    for (int step = 1; step <= 300; ++step) {
        ASSERT_TRUE(cpu.step().ok()) << "step " << step;
        ASSERT_TRUE(device.step().ok()) << "step " << step;
    }
    const BodyState top = device.body(10);
    EXPECT_LT(std::hypot(top.position.x, top.position.z), 0.02);
    EXPECT_NEAR(top.position.y, cpu.body(10).position.y, 0.01);
    EXPECT_GT(top.position.y, 9.45) << "the stack has not sunk or fallen";
    EXPECT_FALSE(top.asleep);
}

// The solver set's pyramid of 20 rows, one crate deep, awake for 600 steps on the colored path
// with its default coloring: after it has settled (step 100) no crate moves by more than 5 mm,
// and none is faster than 5 mm/s at the end. A wall one crate deep sways out of its plane when
// the colors let a pass push its edge crates back and forth (the host's coloring by support
// leaves it swaying at about 0.1 m/s); the CPU's soft step settles it within 2.5 mm.
TEST_F(SoftStepTwin, ColoredWallOfTwentyRowsComesToRest) {
    Result<Scene> loaded =
        loadScene(std::string(RUBBLE_SOURCE_DIR) + "/scenes/solver/pyramid_20.json");
    ASSERT_TRUE(loaded.ok()) << loaded.error().describe();
    Scene scene = *loaded;
    scene.simulation.sleep = false;
    World device = world(scene, Backend::OpenCl, 0);
    std::vector<glm::vec3> settled;
    for (int step = 1; step <= 600; ++step) {
        ASSERT_TRUE(device.step().ok()) << "step " << step;
        if (step == 100) settled = test::positionsOf(device);
    }
    float moved = 0.0f, fastest = 0.0f;
    for (std::uint32_t i = 0; i < device.bodyCount(); ++i) {
        moved = std::max(moved, glm::length(device.body(i).position - settled[i]));
        fastest = std::max(fastest, glm::length(device.body(i).linearVelocity));
    }
    std::printf("[ colored soft step ] largest move after step 100 %.4f m, fastest %.4f m/s\n",
                moved, fastest);
    EXPECT_LT(moved, 0.005f);
    EXPECT_LT(fastest, 0.005f);
}

// Particle contacts have no pairs, plan or rows for the soft step: refused, naming the field.
TEST_F(SoftStepTwin, ParticleContactsAreRefused) {
    Scene scene = sceneOf(crates(R"({"name": "c", "shape": "crate", "mass": 1,
                                     "position": [0, 0.5, 0]})"));
    scene.simulation.backend = Backend::OpenCl;
    scene.simulation.collision.method = CollisionMethod::Particles;
    RunOptions run;
    run.context = context();
    Result<World> w = World::create(scene, run);
    ASSERT_FALSE(w.ok());
    EXPECT_EQ(w.error().kind, ErrorKind::NotSupported);
    EXPECT_NE(w.error().where.find("simulation.solver.type"), std::string::npos);
    EXPECT_NE(w.error().message.find("sat contacts only"), std::string::npos) << w.error().message;
}

} // namespace
} // namespace rubble
