// tests/physics/contact_recycling_test.cpp: resting stacks with contact recycling
// (simulation.collision.recycle_contacts, docs/collision.md) stand as they do without it.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "physics_util.h"

namespace rubble {
namespace {

struct Settled {
    float worstSideways = 0.0f; // largest horizontal drift of any box from its start, m
    float worstDown = 0.0f;     // largest sinking of any box below its start, m
    std::uint32_t asleep = 0;   // bodies asleep after the last step
};

// 10 s of the scene at its 60 Hz and 10 iterations, recycling as asked.
Settled settle(const std::string& file, bool recycle) {
    Scene scene = test::shippedScene(file);
    scene.simulation.collision.recycleContacts = recycle;
    World world = test::makeWorld(scene);
    std::vector<glm::vec3> start;
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) start.push_back(world.body(i).position);
    Settled s;
    for (int step = 0; step < 600; ++step) {
        EXPECT_TRUE(test::stepWorld(world, 1)) << file << " step " << step;
        for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
            const glm::vec3 d = world.body(i).position - start[i];
            s.worstSideways = std::max(s.worstSideways, std::sqrt(d.x * d.x + d.z * d.z));
            s.worstDown = std::max(s.worstDown, -d.y);
        }
    }
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) s.asleep += world.body(i).asleep ? 1 : 0;
    return s;
}

// The stack and the pyramid stand within the bounds of tests/physics/contact_test.cpp, sink no
// more than a millimetre deeper than without recycling, and fall asleep.
void expectStandsRecycling(const std::string& file) {
    const Settled on = settle(file, true), off = settle(file, false);
    EXPECT_LT(on.worstSideways, 0.1f) << file;
    EXPECT_LT(on.worstDown, 0.06f) << file;
    EXPECT_LT(on.worstDown, off.worstDown + 0.001f) << file;
    EXPECT_EQ(on.asleep, test::makeWorld(test::shippedScene(file)).bodyCount() - 1)
        << file << ": everything but the floor settles";
}

TEST(ContactRecycling, StackOfTenStands) {
    expectStandsRecycling("stack_10.json");
}

TEST(ContactRecycling, PyramidOfTwentyStands) {
    expectStandsRecycling("pyramid_20.json");
}

} // namespace
} // namespace rubble
