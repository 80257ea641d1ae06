// tests/unit/scenes_validate_test.cpp: every scene shipped in scenes/ is named here, loads,
// builds without a warning (but for the solver set's scenes past the mass ratio) and takes a
// step with every state finite.
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "rubble/world.h"

namespace rubble {
namespace {

// The shipped scenes, relative to scenes/: a scene added there must be added here too.
const std::set<std::string> kShipped = {"bench/debris_16k.json",
                                        "bench/debris_1k.json",
                                        "bench/debris_4k.json",
                                        "bench/debris_64k.json",
                                        "bench/wall_volley_1k.json",
                                        "bench/wall_volley_mesh_1k.json",
                                        "bench/junkyard.json",
                                        "bench/large_pyramid.json",
                                        "bench/many_pyramids.json",
                                        "bounce.json",
                                        "box_rest.json",
                                        "chain.json",
                                        "city_block.json",
                                        "door.json",
                                        "explosion.json",
                                        "pendulum.json",
                                        "pile_1000.json",
                                        "pile_4096.json",
                                        "pyramid_20.json",
                                        "ragdoll.json",
                                        "ragdoll_pile.json",
                                        "rock_pile.json",
                                        "slope_above_friction.json",
                                        "slope_below_friction.json",
                                        "solver/arch.json",
                                        "solver/card_house.json",
                                        "solver/chain_40.json",
                                        "solver/confined.json",
                                        "solver/friction_ramp.json",
                                        "solver/heavy_on_light_100.json",
                                        "solver/heavy_on_light_1000.json",
                                        "solver/light_under_heavy.json",
                                        "solver/overlap_recovery.json",
                                        "solver/pyramid_20.json",
                                        "solver/ragdoll_pile.json",
                                        "solver/stack_20.json",
                                        "stack_10.json",
                                        "terrain.json"};

// Scenes of the solver test set that go past the mass ratio on purpose: they warn, once.
const std::set<std::string> kPastTheMassRatio = {"solver/heavy_on_light_1000.json"};

TEST(ShippedScenes, EveryOneIsListedLoadsBuildsAndSteps) {
    const std::filesystem::path root = std::string(RUBBLE_SOURCE_DIR) + "/scenes";
    std::set<std::string> found;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root))
        if (entry.path().extension() == ".json")
            found.insert(entry.path().lexically_relative(root).generic_string());
    EXPECT_EQ(found, kShipped) << "scenes/ and the list differ";
    for (const std::string& name : kShipped) {
        SCOPED_TRACE(name);
        Result<Scene> scene = loadScene((root / name).string());
        ASSERT_TRUE(scene.ok()) << scene.error().describe();
        Result<World> world = World::create(*scene);
        ASSERT_TRUE(world.ok()) << world.error().describe();
        if (kPastTheMassRatio.count(name))
            EXPECT_EQ(world->warnings().size(), 1u);
        else
            for (const Warning& w : world->warnings()) ADD_FAILURE() << w.describe();
        // World::step checks that every state stays finite.
        Status step = world->step();
        EXPECT_TRUE(step.ok()) << (step.ok() ? "" : step.error().describe());
        EXPECT_EQ(world->stepIndex(), 1);
    }
}

} // namespace
} // namespace rubble
