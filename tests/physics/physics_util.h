// tests/physics/physics_util.h: helpers shared by the physics tests: the shipped scenes, worlds
// from scenes (stepping with a check is support/test_util.h's stepWorld).
#pragma once

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "rubble/world.h"
#include "support/test_util.h"

namespace rubble::test {

/// A scene from the repository's scenes/ folder; fails the test when it does not load.
inline Scene shippedScene(const std::string& name) {
    Result<Scene> scene = loadScene(std::string(RUBBLE_SOURCE_DIR) + "/scenes/" + name);
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
    if (!scene.ok()) std::abort();
    return std::move(*scene);
}

/// The world of a scene; fails the test when it cannot be built.
inline World makeWorld(const Scene& scene) {
    Result<World> world = World::create(scene);
    EXPECT_TRUE(world.ok()) << (world.ok() ? "" : world.error().describe());
    if (!world.ok()) std::abort();
    return std::move(*world);
}

} // namespace rubble::test
