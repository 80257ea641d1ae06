// tests/physics/ragdoll_fall_test.cpp: the ragdoll of scenes/ragdoll.json falls, lands and comes
// to rest without jitter, its joints holding.
#include <vector>

#include <gtest/gtest.h>

#include "host/io/metrics.h"
#include "physics/physics_util.h"
#include "support/floor_reach.h"

namespace rubble {
namespace {

// Largest distance between the two bodies' copies of each joint's anchor, m; the anchors are
// taken from the initial state.
struct AnchorProbe {
    std::vector<JointDesc> joints;
    std::vector<glm::vec3> inA, inB;

    AnchorProbe(const Scene& scene, const World& world) : joints(scene.joints) {
        for (const JointDesc& j : joints) {
            const BodyState a = world.body(j.a), b = world.body(j.b);
            inA.push_back(glm::inverse(a.orientation) * (j.anchor - a.position));
            inB.push_back(glm::inverse(b.orientation) * (j.anchor - b.position));
        }
    }
    float worst(const World& world) const {
        float w = 0.0f;
        for (std::size_t k = 0; k < joints.size(); ++k) {
            const BodyState a = world.body(joints[k].a), b = world.body(joints[k].b);
            const glm::vec3 pa = a.position + a.orientation * inA[k];
            const glm::vec3 pb = b.position + b.orientation * inB[k];
            w = std::max(w, glm::length(pb - pa));
        }
        return w;
    }
};

TEST(RagdollFall, FallsLandsAndRestsWithJointsHeld) {
    const Scene scene = test::shippedScene("ragdoll.json");
    ASSERT_EQ(scene.joints.size(), 9u);
    World world = test::makeWorld(scene);
    const AnchorProbe probe(scene, world);
    const std::uint32_t chest = *world.findBody("doll_chest");
    const float chestStart = world.body(chest).position.y;
    float stretch = 0.0f, lowestChest = chestStart;
    int restingSince = -1;
    double deepestEver = 0.0;
    // Until something touches the floor the whole doll falls freely: symplectic Euler puts the
    // chest g h^2 n (n + 1) / 2 below its start after n steps.
    const double g = 9.81, h = world.options().dt;
    int freeSteps = 0;
    double worstFreeFall = 0.0;
    for (int step = 0; step < 600; ++step) { // 10 s at 60 Hz
        ASSERT_TRUE(test::stepWorld(world, 1));
        if (freeSteps == step && world.lastStep().contactCount == 0) {
            const double n = step + 1, fallen = g * h * h * n * (n + 1.0) / 2.0;
            worstFreeFall =
                std::max(worstFreeFall,
                         std::abs(double(chestStart - world.body(chest).position.y) - fallen));
            freeSteps = step + 1;
        }
        stretch = std::max(stretch, probe.worst(world));
        deepestEver = std::max(deepestEver, test::deepestBelowFloor(world).depth);
        lowestChest = std::min(lowestChest, world.body(chest).position.y);
        bool allAsleep = true;
        for (std::uint32_t i = 0; i < world.bodyCount(); ++i)
            allAsleep = allAsleep && (world.body(i).isStatic || world.body(i).asleep);
        if (allAsleep && restingSince < 0) restingSince = step;
        // Once at rest it stays at rest: no jitter wakes it.
        if (restingSince >= 0) {
            EXPECT_TRUE(allAsleep) << "woke at step " << step;
        }
    }
    // It falls freely, twenty steps and more, until the floor comes within a step's reach of a
    // foot; the chest then ends lying on the ground.
    EXPECT_GE(freeSteps, 20) << "steps of free fall before the first contact";
    EXPECT_LT(worstFreeFall, 1e-4) << "m off the free fall's closed form";
    EXPECT_LT(lowestChest, 0.5f) << "and lies on the ground";
    EXPECT_LT(stretch, 0.02f);
    ASSERT_GE(restingSince, 0) << "it never came to rest";
    EXPECT_LT(restingSince, 480) << "it takes too long to settle";
    // Nothing sank into the floor: at rest every body's lowest point is within the contacts'
    // 5 mm slop of it, and on the way no body went deeper than part of a step's travel at the
    // landing speed (3.8 m/s: 6 cm a step).
    const test::FloorReach sunk = test::deepestBelowFloor(world);
    EXPECT_LT(sunk.depth, 0.006) << "m, " << sunk.name << "'s lowest point below the floor";
    EXPECT_LT(deepestEver, 0.04) << "m below the floor at the deepest, on the way";
}

TEST(RagdollFall, SettlesWithoutJitterBeforeSleeping) {
    // After the landing the kinetic energy decays window by window, with nothing pumping it.
    World world = test::makeWorld(test::shippedScene("ragdoll.json"));
    ASSERT_TRUE(test::stepWorld(world, 90)); // 1.5 s: landed
    double previous = 1e9;
    for (int window = 0; window < 4; ++window) { // half-second windows up to 3.5 s
        double worst = 0.0;
        for (int step = 0; step < 30; ++step) {
            ASSERT_TRUE(test::stepWorld(world, 1));
            worst = std::max(worst, measureInvariants(world).kineticEnergy);
        }
        EXPECT_LE(worst, previous) << "window " << window;
        previous = worst;
    }
    EXPECT_LT(previous, 0.05) << "J, for 70 kg: below 4 cm/s";
}

} // namespace
} // namespace rubble
