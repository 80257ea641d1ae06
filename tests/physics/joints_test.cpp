// tests/physics/joints_test.cpp: ball and hinge joints hold their anchors and axes while a chain
// whips and doors swing (scenes/chain.json, scenes/door.json and a flap).
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "host/io/metrics.h"
#include "physics/physics_util.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// A joint's anchor and axis in both bodies' frames, taken from the initial state, so that the
// test measures the joints without the solver's own bookkeeping.
struct Probe {
    std::uint32_t a = 0, b = 0;
    glm::vec3 anchorA{0.0f}, anchorB{0.0f}, axisA{0.0f}, axisB{0.0f};
    bool hinge = false;
};

std::vector<Probe> probes(const Scene& scene, const World& world) {
    std::vector<Probe> out;
    for (const JointDesc& j : scene.joints) {
        const BodyState a = world.body(j.a), b = world.body(j.b);
        Probe p;
        p.a = j.a;
        p.b = j.b;
        p.anchorA = glm::inverse(a.orientation) * (j.anchor - a.position);
        p.anchorB = glm::inverse(b.orientation) * (j.anchor - b.position);
        p.axisA = glm::inverse(a.orientation) * j.axis;
        p.axisB = glm::inverse(b.orientation) * j.axis;
        p.hinge = j.type == JointType::Hinge;
        out.push_back(p);
    }
    return out;
}

struct Worst {
    float separation = 0.0f; // m
    float axisDegrees = 0.0f;
};

void measure(const World& world, const std::vector<Probe>& ps, Worst& worst) {
    for (const Probe& p : ps) {
        const BodyState a = world.body(p.a), b = world.body(p.b);
        const glm::vec3 pa = a.position + a.orientation * p.anchorA;
        const glm::vec3 pb = b.position + b.orientation * p.anchorB;
        worst.separation = std::max(worst.separation, glm::length(pb - pa));
        if (!p.hinge) continue;
        const float c =
            glm::clamp(glm::dot(a.orientation * p.axisA, b.orientation * p.axisB), -1.0f, 1.0f);
        worst.axisDegrees =
            std::max(worst.axisDegrees, float(std::acos(c) * 180.0 / std::numbers::pi));
    }
}

TEST(Joints, WhippingChainKeepsItsAnchors) {
    const Scene scene = test::shippedScene("chain.json");
    World world = test::makeWorld(scene);
    const std::vector<Probe> ps = probes(scene, world);
    const std::uint32_t tip = *world.findBody("link9");
    Worst worst;
    float tipSpeed = 0.0f;
    for (int i = 0; i < 300; ++i) { // 5 s at 60 Hz
        ASSERT_TRUE(world.step().ok());
        measure(world, ps, worst);
        tipSpeed = std::max(tipSpeed, glm::length(world.body(tip).linearVelocity));
    }
    EXPECT_GT(tipSpeed, 6.0f) << "the chain should whip";
    EXPECT_LT(worst.separation, 0.005f);
}

TEST(Joints, SwingingDoorKeepsItsHinge) {
    const Scene scene = test::shippedScene("door.json");
    World world = test::makeWorld(scene);
    const std::vector<Probe> ps = probes(scene, world);
    const std::uint32_t door = *world.findBody("door");
    Worst worst;
    double turned = 0.0;
    for (int i = 0; i < 300; ++i) {
        ASSERT_TRUE(world.step().ok());
        measure(world, ps, worst);
        turned += double(world.body(door).angularVelocity.y) * world.options().dt;
    }
    EXPECT_GT(turned, 2.0 * std::numbers::pi) << "the door should swing round";
    EXPECT_LT(worst.separation, 0.005f);
    EXPECT_LT(worst.axisDegrees, 1.0f);
    // Gravity does no work about a vertical hinge and the rows' impulses act at the anchor:
    // the door keeps its 3 rad/s. Rows asking for no speed at the anchor would keep the centre
    // moving along the last step's tangent, and the projection (velocities untouched) would
    // take f/2 (w h)^2 of the speed a step, f = m r^2 / (I + m r^2): 2.40 rad/s after 5 s.
    EXPECT_NEAR(world.body(door).angularVelocity.y, 3.0f, 0.003f) << "rad/s after 5 s";
    std::printf("[ door ] %.4f rad/s after 5 s\n", double(world.body(door).angularVelocity.y));
}

TEST(Joints, FallingFlapKeepsItsHinge) {
    // A 1 m flap on a horizontal hinge, released level: gravity swings it down and back.
    World world = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "shapes": {"post": {"type": "box", "half_extents": [0.05, 0.05, 0.5]},
                 "flap": {"type": "box", "half_extents": [0.5, 0.02, 0.4]}},
      "bodies": [{"name": "post", "shape": "post", "static": true, "position": [0, 2, 0]},
                 {"name": "flap", "shape": "flap", "mass": 4.0, "position": [0.55, 2, 0]}],
      "joints": [{"type": "hinge", "a": "post", "b": "flap", "anchor": [0.05, 2, 0],
                  "axis": [0, 0, 1]}]})");
    Probe p;
    p.a = 0;
    p.b = 1;
    p.anchorA = {0.05f, 0.0f, 0.0f};
    p.anchorB = {-0.5f, 0.0f, 0.0f};
    p.axisA = p.axisB = {0.0f, 0.0f, 1.0f};
    p.hinge = true;
    Worst worst;
    float lowest = 2.0f, back = 0.0f;
    for (int i = 0; i < 240; ++i) {
        ASSERT_TRUE(world.step().ok());
        measure(world, {p}, worst);
        const float y = world.body(1).position.y;
        lowest = std::min(lowest, y);
        if (lowest < 1.55f) back = std::max(back, y);
    }
    EXPECT_LT(lowest, 1.52f) << "the flap should swing down"; // 1.5 hanging straight
    // Nothing takes energy from a frictionless hinge: the flap swings back up to level (rows
    // asking for no speed at the anchor would leave it centimetres short).
    EXPECT_GT(back, 2.0f - 0.001f) << "m, the flap's centre on its way back up";
    std::printf("[ flap ] back up %.1f mm short of level\n", double(2.0f - back) * 1000.0);
    EXPECT_LT(worst.separation, 0.005f);
    EXPECT_LT(worst.axisDegrees, 1.0f);
}

} // namespace
} // namespace rubble
