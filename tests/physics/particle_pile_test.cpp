// tests/physics/particle_pile_test.cpp: a deep block of crates on the particle path (the CPU twin
// of the device's stages: voxel particles and the per-row Jacobi solver at 10 iterations) falls,
// collapses and comes to rest: no creep, nothing sunk; a stack and a pyramid of 8-particle crates
// solved by PGS stand and sleep.
#include <gtest/gtest.h>

#include "physics/physics_util.h"
#include "support/floor_reach.h"
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
// them would ask the Baumgarte term for a separating speed that the 10-sweep Jacobi solve turns
// into motion, and the block would creep on. Particle contacts leave a tenth of the spacing
// uncorrected (rubble/shared/contact_row.h, particleSlopItem), and no crate's lowest particle
// is deeper in the floor than that.
TEST(ParticlePile, DeepBlockComesToRestAtTenIterations) {
    World world = test::worldFromText(kBlock);
    ASSERT_TRUE(test::stepWorld(world, 900)); // 15 s
    std::uint32_t asleep = 0;
    double energy = 0.0;
    for (std::uint32_t i = 1; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        asleep += b.asleep ? 1u : 0u;
        energy += 0.5 * double(glm::dot(b.linearVelocity, b.linearMomentum) +
                               glm::dot(b.angularVelocity, b.angularMomentum));
    }
    EXPECT_EQ(world.bodyCount(), 433u);
    // Each crate as its particles (radius 0.25 m): the slop is 0.05 m.
    const test::FloorReach sunk = test::deepestBelowFloor(world, 0.25);
    EXPECT_LT(sunk.depth, 0.055) << "m, " << sunk.name << "'s lowest particle below the floor";
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
// from the first step: contacts made only at an overlap would leave the crates above the
// highest contact falling together (free fall: 0.15 m in ten steps) until the stack below had
// sunk far enough. The stack stands and sleeps; the particles' scattered order keeps the sweeps
// from meeting the same corner of each face first (in the voxeliser's rows it sways aside).
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
// sleeps at its 10 sweeps: the particles' scattered order keeps every sweep from meeting the
// same corner of each face first (in the voxeliser's rows the pyramid falls).
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
