// tests/unit/scenes_validate_test.cpp: every scene shipped in scenes/ loads and builds.
#include <filesystem>

#include <gtest/gtest.h>

#include "rubble/world.h"

namespace rubble {
namespace {

TEST(ShippedScenes, EveryOneValidates) {
    int count = 0;
    for (const auto& entry :
         std::filesystem::recursive_directory_iterator(std::string(RUBBLE_SOURCE_DIR) + "/scenes")) {
        if (entry.path().extension() != ".json") continue;
        ++count;
        Result<Scene> scene = loadScene(entry.path().string());
        ASSERT_TRUE(scene.ok()) << scene.error().describe();
        Result<World> world = World::create(*scene);
        EXPECT_TRUE(world.ok()) << world.error().describe();
    }
    EXPECT_GE(count, 4);
}

} // namespace
} // namespace rubble
