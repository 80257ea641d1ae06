// tests/gpu/particle_pgs_test.cpp: particle contacts solved by projected Gauss-Seidel on the
// device (--collision particles --solver pgs): each contact a pair of one point, sorted by pair
// as the CPU orders its manifolds (particleContactsToManifolds), so that in one block the device
// steps the CPU's particles and PGS bit for bit; and crates that rest and fall asleep in the
// device's own blocks and colors.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gpu_fixture.h"

namespace rubble {
namespace {

class ParticlePgs : public test::GpuTest {
  protected:
    // A world of `json` with particles and PGS, on the device in `blocks` (RunOptions::
    // pgsBlocks: -1 as the device suits, 0 every element colored) or on the CPU.
    World world(const std::string& json, Backend backend, int blocks = -1) {
        return worldOf(sceneOf(json), backend, CollisionMethod::Particles, SolverType::Pgs, blocks);
    }
};

// Six crates (8 particles each at 0.5 m, 56 at 0.25 m) dropped turned onto the floor and onto
// each other, one sliding in at 2 m/s, one bouncy (restitution 0.6) onto another: contacts
// between particles, with the floor, that push apart (the split position pass), bounce and
// slide, warm-started from step to step; nothing comes to rest within the 45 steps (0.75 s), so
// that neither side sleeps.
std::string tumble(const char* spacing) {
    return std::string(R"({"format": "rubble-scene", "version": 1, "name": "tumble",
  "simulation": {"dt": 0.016666667, "solver": {"iterations": 10},
                 "collision": {"particle_spacing": )") +
           spacing + R"(}},
  "materials": {"default": {"friction": 0.5, "restitution": 0.0},
                "bouncy": {"friction": 0.4, "restitution": 0.6}},
  "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
  "bodies": [{"name": "floor", "shape": "ground", "static": true},
    {"name": "c0", "shape": "crate", "mass": 1, "position": [0, 0.6, 0],
     "orientation": [0.995, 0.05, 0.07, 0.02], "linear_velocity": [0, -1, 0]},
    {"name": "c1", "shape": "crate", "mass": 2, "position": [0.3, 1.75, 0.2],
     "orientation": [0.99, 0.0, 0.1, 0.1], "linear_velocity": [0, -2, 0]},
    {"name": "c2", "shape": "crate", "mass": 1, "position": [-2.5, 0.52, 0],
     "linear_velocity": [2, 0, 0]},
    {"name": "c3", "shape": "crate", "mass": 1, "position": [-1.1, 0.7, 0.1],
     "orientation": [0.98, 0.1, 0.0, 0.15], "linear_velocity": [0, -0.5, 0]},
    {"name": "c4", "shape": "crate", "mass": 1, "material": "bouncy", "position": [0.2, 3.2, -0.1],
     "linear_velocity": [0, -3, 0], "angular_velocity": [1, 0, 0.5]},
    {"name": "c5", "shape": "crate", "mass": 1, "position": [1.3, 0.55, 0.9],
     "orientation": [0.97, 0.0, 0.0, 0.24], "linear_velocity": [-0.5, 0, 0]}]})";
}

// In one block the device's sweeps go through the rows in the CPU's order (the contacts sorted
// by pair, then by particles): every body the same to the bit at every step, with 8 particles a
// crate (at most 4 contacts a pair) and with 56 (up to 16 a pair: each contact warm-starts from
// its own feature among all of the pair's, on the CPU as on the device; the CPU's search among a
// SAT manifold's first 8 old points parted the two at the second step). A world this small gets
// one block when the device chooses (kPgsBlockBodies). In eight blocks, as a large world gets
// them, the order is not the CPU's and the two part once two crates touch.
TEST_F(ParticlePgs, OneBlockStepsTheCpuBitForBit) {
    for (const auto& [spacing, blocks] :
         {std::pair{"0.5", 1}, {"0.25", 1}, {"0.5", -1}, {"0.25", -1}}) {
        SCOPED_TRACE("blocks " + std::to_string(blocks));
        World cpu = world(tumble(spacing), Backend::Cpu);
        World device = world(tumble(spacing), Backend::OpenCl, blocks);
        std::uint32_t touched = 0;
        for (int step = 1; step <= 45; ++step) {
            ASSERT_TRUE(cpu.step().ok()) << "step " << step;
            ASSERT_TRUE(device.step().ok()) << "step " << step;
            EXPECT_EQ(device.lastStep().contactCount, cpu.lastStep().contactCount)
                << "spacing " << spacing << ", step " << step;
            touched = std::max(touched, cpu.lastStep().contactCount);
            for (std::uint32_t i = 0; i < cpu.bodyCount(); ++i) {
                const BodyState a = cpu.body(i), b = device.body(i);
                ASSERT_TRUE(test::sameBits(a, b))
                    << "spacing " << spacing << ", body " << i << " at step " << step
                    << ": position (" << a.position.x << ", " << a.position.y << ", "
                    << a.position.z << ") against (" << b.position.x << ", " << b.position.y << ", "
                    << b.position.z << ")";
                ASSERT_FALSE(b.asleep) << "body " << i << " at step " << step;
            }
        }
        std::printf("[ spacing %s ] at most %u contacts\n", spacing, touched);
        EXPECT_GE(touched, 12u); // the pile's contacts, not a free fall
    }
}

// A scene of 1 kg crates of side 1 m, 8 particles each, on the floor at `iterations` sweeps, one
// at each of `centres`.
std::string cratesScene(int iterations, const std::vector<glm::vec3>& centres) {
    std::string json = R"({"format": "rubble-scene", "version": 1, "name": "crates",
      "simulation": {"dt": 0.016666667, "solver": {"iterations": )" +
                       std::to_string(iterations) + R"(},
                     "collision": {"particle_spacing": 0.5}},
      "materials": {"default": {"friction": 0.5, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true})";
    for (std::size_t i = 0; i < centres.size(); ++i)
        json += ", {\"name\": \"c" + std::to_string(i) +
                "\", \"shape\": \"crate\", \"mass\": 1, \"position\": [" +
                std::to_string(centres[i].x) + ", " + std::to_string(centres[i].y) + ", " +
                std::to_string(centres[i].z) + "]}";
    return json + "]}";
}

// Four crates side by side on the floor and one across two of them, 8 particles each: they
// stand, sink no more than a few millimetres and fall asleep, in the device's blocks and with
// every element colored (as a GPU runs it).
TEST_F(ParticlePgs, CratesStandAndSleepInBlocksAndColored) {
    std::vector<glm::vec3> centres;
    for (int i = 0; i < 4; ++i) centres.push_back({1.2f * float(i), 0.5f, 0.0f});
    centres.push_back({0.6f, 1.5f, 0.0f}); // across the first two
    const std::string json = cratesScene(10, centres);
    for (const int blocks : {-1, 8, 0}) {
        World w = world(json, Backend::OpenCl, blocks);
        const std::vector<glm::vec3> start = test::positionsOf(w);
        ASSERT_TRUE(test::stepWorld(w, 300)) << "blocks " << blocks;
        float moved = 0.0f, lowest = 1e9f;
        std::uint32_t asleep = 0;
        for (std::uint32_t i = 1; i < w.bodyCount(); ++i) {
            moved = std::max(moved, glm::length(w.body(i).position - start[i]));
            if (i < 5) lowest = std::min(lowest, w.body(i).position.y);
            asleep += w.body(i).asleep ? 1u : 0u;
        }
        std::printf("[ blocks %d ] largest displacement %.4f m, lowest centre %.4f m, %u of 5 "
                    "asleep\n",
                    blocks, moved, lowest, asleep);
        EXPECT_LT(moved, 0.02f) << "blocks " << blocks;
        EXPECT_GT(lowest, 0.495f) << "blocks " << blocks;
        EXPECT_EQ(asleep, 5u) << "blocks " << blocks;
    }
}

// A stack of ten 8-particle crates (stack_10's) at the scene's 10 sweeps, in the device's blocks
// and colored: it stands and sleeps in both. Its crates start touching, at a gap of zero: the
// contacts' speculative margin holds them from the first step (without it the crates above the
// last contact fall freely until the stack below has sunk, and the stack falls), and the
// particles' scattered order keeps the sweeps from meeting the same corner of each face first
// (in the voxeliser's rows the stack sways aside).
TEST_F(ParticlePgs, ATallStackStandsInBlocksAndColored) {
    std::vector<glm::vec3> centres;
    for (int i = 0; i < 10; ++i) centres.push_back({0.0f, 0.5f + float(i), 0.0f});
    const std::string json = cratesScene(10, centres);
    for (const int blocks : {-1, 8, 0}) {
        World w = world(json, Backend::OpenCl, blocks);
        const std::vector<glm::vec3> start = test::positionsOf(w);
        ASSERT_TRUE(test::stepWorld(w, 600)) << "blocks " << blocks;
        const test::Settled s = test::settledSince(w, start);
        std::printf("[ blocks %d ] largest drop %.4f m, %.4f m aside, %u of 10 asleep\n", blocks,
                    s.drop, s.aside, s.asleep);
        EXPECT_LT(s.drop, 0.05f) << "blocks " << blocks; // fallen, it is metres
        EXPECT_LT(s.aside, 0.15f) << "blocks " << blocks;
        EXPECT_EQ(s.asleep, 10u) << "blocks " << blocks;
    }
}

} // namespace
} // namespace rubble
