// tests/gpu/islands_twin_test.cpp: islands and their sleep on the device (DeviceIslands,
// kernels/islands.cl) against the CPU's (host/dynamics/islands.cpp): two stacks and a jointed pair
// fall asleep, a crate dropped on one stack wakes it whole, and every step the device's asleep
// flags are the CPU's islands' and its bodies the CPU's bits.
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "gpu_fixture.h"
#include "host/dynamics/islands.h"
#include "rubble/shared/sleep.h"
#include "support/physics_cases.h"

namespace rubble {
namespace {

// The device's thresholds are the CPU's.
static_assert(RUBBLE_ISLAND_SLEEP_SPEED == kSleepSpeed);
static_assert(RUBBLE_ISLAND_SLEEP_TIME == kTimeToSleep);

// Two stacks of three unit crates 6 m apart, two crates side by side joined by a ball joint
// (one island through the joint, not through a contact), and a crate 14 m up over the left
// stack, which it reaches after about 1.5 s, when the rest has slept for a while.
const char* kDropScene = R"({"format": "rubble-scene", "version": 1, "name": "drop",
  "simulation": {"dt": 0.016666667, "solver": {"type": "pgs", "iterations": 10}},
  "materials": {"default": {"friction": 0.6, "restitution": 0.0}},
  "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
  "bodies": [
    {"name": "floor", "shape": "ground", "static": true},
    {"name": "left0", "shape": "crate", "mass": 1, "position": [-3, 0.5, 0]},
    {"name": "left1", "shape": "crate", "mass": 1, "position": [-3.02, 1.5, 0.01]},
    {"name": "left2", "shape": "crate", "mass": 1, "position": [-2.97, 2.5, -0.02]},
    {"name": "right0", "shape": "crate", "mass": 1, "position": [3, 0.5, 0]},
    {"name": "right1", "shape": "crate", "mass": 1, "position": [3.03, 1.5, 0]},
    {"name": "right2", "shape": "crate", "mass": 1, "position": [2.99, 2.5, 0.02]},
    {"name": "pairA", "shape": "crate", "mass": 1, "position": [-0.55, 0.5, 4]},
    {"name": "pairB", "shape": "crate", "mass": 1, "position": [0.55, 0.5, 4]},
    {"name": "dropped", "shape": "crate", "mass": 2, "position": [-2.9, 14, 0.05],
     "orientation": [0.9998, 0.01, 0.02, 0]}],
  "joints": [{"type": "ball", "a": "pairA", "b": "pairB", "anchor": [0, 0.5, 4]}]})";

class IslandsTwin : public test::GpuTest {
  protected:
    World world(Backend backend) {
        return worldOf(sceneOf(kDropScene), backend, CollisionMethod::Sat, SolverType::Pgs);
    }
};

std::vector<std::uint8_t> asleepFlags(const World& w) {
    std::vector<std::uint8_t> out;
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) out.push_back(w.body(i).asleep ? 1 : 0);
    return out;
}

// The device's islands decide as the CPU's, step by step: the stacks and the jointed pair fall
// asleep, the dropped crate wakes the left stack (the whole of it, in the step it lands: its
// group) but not the right one and knocks it over, and the left stack's crates and the dropped
// one sleep again.
// The small world runs as one block, in the CPU's order, so every body keeps the CPU's bits.
TEST_F(IslandsTwin, PilesSleepAndWakeAsTheCpuIslandsDecide) {
    World cpu = world(Backend::Cpu);
    World device = world(Backend::OpenCl);
    const std::uint32_t n = cpu.bodyCount(), dropped = n - 1;
    const std::vector<std::uint32_t> left = {1, 2, 3}, right = {4, 5, 6}, pair = {7, 8};
    int allRestingAsleep = -1, leftWoken = -1, asleepAgain = -1;
    bool rightWoke = false;
    std::vector<glm::vec3> resting;
    for (int step = 1; step <= 420; ++step) {
        ASSERT_TRUE(cpu.step().ok()) << "step " << step;
        ASSERT_TRUE(device.step().ok()) << "step " << step;
        const std::vector<std::uint8_t> c = asleepFlags(cpu), d = asleepFlags(device);
        for (std::uint32_t i = 0; i < n; ++i) {
            ASSERT_EQ(d[i], c[i]) << device.bodyName(i) << " asleep at step " << step;
            ASSERT_TRUE(test::sameBits(cpu.body(i), device.body(i)))
                << cpu.bodyName(i) << " at step " << step;
        }
        ASSERT_EQ(device.lastStep().asleep, cpu.lastStep().asleep) << "step " << step;
        auto all = [&](const std::vector<std::uint32_t>& bodies, std::uint8_t asleep) {
            for (std::uint32_t i : bodies)
                if (d[i] != asleep) return false;
            return true;
        };
        if (allRestingAsleep < 0 && all(left, 1) && all(right, 1) && all(pair, 1)) {
            allRestingAsleep = step;
            resting = test::positionsOf(device);
        }
        // Woken as one: every body of the stack in the same step.
        if (allRestingAsleep > 0 && leftWoken < 0 && !all(left, 1)) {
            EXPECT_TRUE(all(left, 0)) << "the left stack wakes whole at step " << step;
            leftWoken = step;
        }
        if (allRestingAsleep > 0 && !all(right, 1)) rightWoke = true;
        if (leftWoken > 0 && asleepAgain < 0 && all(left, 1) && d[dropped]) asleepAgain = step;
    }
    std::printf("[ drop ] resting bodies asleep at step %d, left stack woken at %d, asleep again "
                "at %d\n",
                allRestingAsleep, leftWoken, asleepAgain);
    ASSERT_GT(allRestingAsleep, 0) << "the stacks and the pair fell asleep";
    EXPECT_LT(allRestingAsleep, 80) << "before the dropped crate lands";
    ASSERT_GT(leftWoken, allRestingAsleep) << "the dropped crate woke the left stack";
    EXPECT_FALSE(rightWoke) << "the right stack slept on";
    EXPECT_GT(asleepAgain, leftWoken) << "the left stack and the dropped crate slept again";
    float knocked = 0.0f;
    for (std::uint32_t i : left)
        knocked = std::max(knocked, glm::length(device.body(i).position - resting[i]));
    EXPECT_GT(knocked, 0.3f) << "m: the woken stack took the hit with its mass";
}

// The island kernels count the bytes they move (host/gpu/traffic.cpp), as every kernel does: the
// jointed touching row falls asleep by islands and is hit, which runs the wake (its bodies, pairs
// and joints passes) and the update (its groups, pairs and joints) on the device.
TEST_F(IslandsTwin, IslandKernelsCountTheirBytes) {
    World w = deviceWorld(test::jointedRowScene(test::kDeviceSatSimulation));
    std::uint32_t asleep = 0;
    for (int i = 0; i < 120; ++i) {
        ASSERT_TRUE(w.step().ok());
        asleep = std::max(asleep, w.lastStep().asleep);
    }
    std::map<std::string, DeviceCommandTime> byName = test::deviceProfileByName(w);
    for (const char* name :
         {"prepareIslands", "markIslandWakeBodies", "markIslandWakePairs", "markIslandWakeJoints",
          "wakeIslandBodies", "measureIslandBodies", "hookIslandGroups", "uniteIslandPairs",
          "uniteIslandJoints", "gatherIslands", "sleepIslands"}) {
        EXPECT_GT(byName[name].launches, 0u) << name;
        EXPECT_GT(byName[name].bytes, 0u) << name;
    }
    EXPECT_GT(asleep, 0u) << "the row fell asleep";
}

} // namespace
} // namespace rubble
