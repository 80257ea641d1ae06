// tests/physics/particle_pile_test.cpp: a deep block of crates on the particle path (the CPU twin
// of the device's stages: voxel particles and the per-row Jacobi solver at 10 iterations) falls,
// collapses and comes to rest: no creep, nothing sunk; a stack and a pyramid of 8-particle crates
// solved by PGS stand and sleep.
#include <gtest/gtest.h>

#include "physics/physics_util.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// 432 crates of 0.5 m half extent in 12 layers (6 x 12 x 6, 1.2 m apart, turned a little), as the
// debris benchmark scenes build them; 8 particles per crate.
const char* kBlock = R"({"format": "rubble-scene", "version": 1, "name": "block",
  "simulation": {"dt": 0.016666666666666666, "integrator": "symplectic",
                 "collision": {"method": "particles", "particle_spacing": 0.5},
                 "solver": {"type": "jacobi", "iterations": 10}},
  "materials": {"default": {"friction": 0.5, "restitution": 0.0}},
  "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
  "bodies": [{"name": "floor", "shape": "floor", "static": true}],
  "generators": [{"type": "grid", "shape": "crate", "mass": 1.0, "count": [6, 12, 6],
                  "origin": [-3, 2, -3], "spacing": [1.2, 1.2, 1.2], "rotation_jitter": 0.1,
                  "seed": 1, "name_prefix": "d"}]})";

// Resting particle contacts are a few centimetres deep; with the scene's 5 mm slop alone each of
// them asked the Baumgarte term for a separating speed that the 10-sweep Jacobi solve turned into
// motion, and such a block still crept at 15 s (5 J, 1.5 m/s at most). Particle contacts leave a
// tenth of the spacing uncorrected (rubble/shared/contact_row.h, particleSlopItem).
TEST(ParticlePile, DeepBlockComesToRestAtTenIterations) {
    World world = test::worldFromText(kBlock);
    ASSERT_TRUE(test::stepWorld(world, 900)); // 15 s
    std::uint32_t asleep = 0, sunk = 0;
    double energy = 0.0;
    for (std::uint32_t i = 1; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        asleep += b.asleep ? 1u : 0u;
        sunk += b.position.y < 0.0f ? 1u : 0u;
        energy += 0.5 * double(glm::dot(b.linearVelocity, b.linearMomentum) +
                               glm::dot(b.angularVelocity, b.angularMomentum));
    }
    EXPECT_EQ(world.bodyCount(), 433u);
    EXPECT_EQ(sunk, 0u);
    EXPECT_EQ(asleep, 432u);
    EXPECT_LT(energy, 1e-3);
}

// A shipped scene of 1 m crates on the CPU's particles, 8 a crate, solved by PGS.
World eightParticleCratesWithPgs(const std::string& name) {
    Scene scene = test::shippedScene(name);
    scene.simulation.collision.method = CollisionMethod::Particles;
    scene.simulation.collision.particleSpacing = 0.5f;
    scene.simulation.solver.type = SolverType::Pgs;
    return test::makeWorld(scene);
}

// stack_10 (ten crates touching, at a gap of zero) on particles solved by PGS: its contacts
// reach the speculative margin (kParticleContactMargin), so every crate rests on the one below
// from the first step. Contacts made only at an overlap left the crates above the highest
// contact falling together until the stack below had sunk far enough: the top crate fell 0.150 m
// in ten steps (9.81 m/s^2, free fall) and struck the stack at 0.27 m/s; now 0.006 m. The stack
// stands and sleeps (the largest drop 0.009 m at step 600, the top crate 0.07 m aside; with its
// particles in the voxeliser's rows it swayed, 0.26 m aside, and never slept: docs/opencl.md).
TEST(ParticlePile, CratesTouchingAtAGapOfZeroRestFromTheFirstStepWithPgs) {
    World world = eightParticleCratesWithPgs("stack_10.json");
    const std::vector<glm::vec3> start = test::positionsOf(world);
    const std::uint32_t top = world.bodyCount() - 1;
    ASSERT_TRUE(test::stepWorld(world, 10));
    EXPECT_LT(start[top].y - world.body(top).position.y, 0.01f);
    ASSERT_TRUE(test::stepWorld(world, 590));
    const test::Settled s = test::settledSince(world, start);
    EXPECT_LT(s.drop, 0.05f);
    EXPECT_LT(s.aside, 0.15f);
    EXPECT_EQ(s.asleep, 10u);
}

// pyramid_20 (210 crates, each on two) of 8-particle crates solved by PGS on the CPU stands and
// sleeps at its 10 sweeps. With the particles in the voxeliser's rows every sweep met the same
// corner of each face first and the pyramid fell (53 crates still moving at step 600); in a
// scattered order the largest drop is 0.027 m and nothing moves (docs/opencl.md).
TEST(ParticlePile, PyramidOfEightParticleCratesStandsWithPgs) {
    World world = eightParticleCratesWithPgs("pyramid_20.json");
    const std::vector<glm::vec3> start = test::positionsOf(world);
    ASSERT_TRUE(test::stepWorld(world, 600));
    const test::Settled s = test::settledSince(world, start);
    EXPECT_EQ(world.bodyCount(), 211u);
    EXPECT_LT(s.drop, 0.1f); // fallen, it is metres
    EXPECT_EQ(s.asleep, 210u);
}

} // namespace
} // namespace rubble
