// tests/physics/contact_test.cpp: contacts against closed forms and plain expectations: a box at
// rest, a stack and a pyramid standing, Coulomb friction on slopes, restitution of a bounce
// (scenes/box_rest, stack_10, pyramid_20, slope_*, bounce).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "physics/physics_util.h"
#include "support/physics_cases.h"
#include "support/test_util.h"

namespace rubble {
namespace {

TEST(Contacts, BoxAtRestStaysAndSleeps) {
    World world = test::makeWorld(test::shippedScene("box_rest.json"));
    const std::uint32_t box = *world.findBody("box");
    const glm::vec3 start = world.body(box).position;
    float drift = 0.0f;
    bool slept = false;
    for (int i = 0; i < 600; ++i) { // 10 s at 60 Hz
        ASSERT_TRUE(test::stepWorld(world, 1));
        drift = std::max(drift, glm::length(world.body(box).position - start));
        slept = slept || world.body(box).asleep;
    }
    EXPECT_LT(drift, 0.001f);
    EXPECT_TRUE(slept);
    EXPECT_TRUE(world.body(box).asleep);
}

// Every box of the scene stays within `sideways` of where it started horizontally, and sinks by
// less than `down`, for 10 s at the scene's 60 Hz and 10 iterations; then all of it sleeps.
void expectStands(const std::string& file, float sideways, float down) {
    const Scene scene = test::shippedScene(file);
    ASSERT_FLOAT_EQ(scene.simulation.dt, 1.0f / 60.0f);
    ASSERT_EQ(scene.simulation.solver.iterations, 10);
    World world = test::makeWorld(scene);
    std::vector<glm::vec3> start;
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) start.push_back(world.body(i).position);
    float worstSideways = 0.0f, worstDown = 0.0f;
    for (int step = 0; step < 600; ++step) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
            const glm::vec3 d = world.body(i).position - start[i];
            worstSideways = std::max(worstSideways, std::sqrt(d.x * d.x + d.z * d.z));
            worstDown = std::max(worstDown, -d.y);
        }
    }
    EXPECT_LT(worstSideways, sideways) << file;
    EXPECT_LT(worstDown, down) << file;
    std::uint32_t asleep = 0;
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) asleep += world.body(i).asleep ? 1 : 0;
    EXPECT_EQ(asleep, world.bodyCount() - 1) << file << ": everything but the floor settles";
}

TEST(Contacts, StackOfTenStands) {
    expectStands("stack_10.json", 0.1f, 0.06f);
}
TEST(Contacts, PyramidOfTwentyStands) {
    expectStands("pyramid_20.json", 0.1f, 0.06f);
}

// The slope scenes: a box on a static ramp turned by the slope angle about z, friction 0.5.
double slopeAngle(const World& world) {
    const glm::quat q = world.body(*world.findBody("ramp")).orientation;
    return 2.0 * std::atan2(double(q.z), double(q.w));
}

// Speed of the box along the slope, m/s (positive downhill).
double downhillSpeed(const World& world, double angle) {
    const glm::dvec3 downhill(-std::cos(angle), -std::sin(angle), 0.0);
    return glm::dot(glm::dvec3(world.body(*world.findBody("box")).linearVelocity), downhill);
}

TEST(Contacts, BoxBelowFrictionAngleStaysPut) {
    World world = test::makeWorld(test::shippedScene("slope_below_friction.json"));
    const double angle = slopeAngle(world);
    ASSERT_LT(std::tan(angle), 0.5);
    const std::uint32_t box = *world.findBody("box");
    const glm::vec3 start = world.body(box).position;
    ASSERT_TRUE(test::stepWorld(world, 180));
    EXPECT_LT(glm::length(world.body(box).position - start), 0.001f);
}

TEST(Contacts, BoxAboveFrictionAngleSlidesWithCoulombAcceleration) {
    World world = test::makeWorld(test::shippedScene("slope_above_friction.json"));
    const double angle = slopeAngle(world);
    const double mu = 0.5;
    ASSERT_GT(std::tan(angle), mu);
    // Settle the first contact, then measure over a second of sliding on the ramp.
    ASSERT_TRUE(test::stepWorld(world, 12));
    const double v0 = downhillSpeed(world, angle), t0 = world.time();
    ASSERT_TRUE(test::stepWorld(world, 60));
    const double v1 = downhillSpeed(world, angle), t1 = world.time();
    const double a = (v1 - v0) / (t1 - t0);
    const double expected = 9.81 * (std::sin(angle) - mu * std::cos(angle));
    // The closed form g (sin - mu cos); 0.1 % leaves room for round-off only.
    EXPECT_NEAR(a / expected, 1.0, 1e-3) << "a = " << a << " m/s^2, expected " << expected;
    // It slides straight down: no sideways drift, no spin.
    const BodyState b = world.body(*world.findBody("box"));
    EXPECT_LT(std::abs(b.linearVelocity.z), 0.01f);
    EXPECT_LT(glm::length(b.angularVelocity), 0.05f);
}

TEST(Contacts, DroppedBoxReboundsToRestitutionSquaredHeight) {
    const Scene scene = test::shippedScene("bounce.json");
    ASSERT_FLOAT_EQ(scene.simulation.dt, 1.0f / 240.0f);
    World world = test::makeWorld(scene);
    const std::uint32_t box = *world.findBody("box");
    const float half = 0.25f; // the box's half height: its bottom face starts 1 m up
    const float drop = world.body(box).position.y - half;
    const float e = 0.5f;
    // Fall, bounce, rise: the apex is where the upward velocity turns.
    bool bounced = false;
    float apex = 0.0f;
    for (int i = 0; i < 480; ++i) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        const BodyState b = world.body(box);
        if (!bounced && b.linearVelocity.y > 0.0f) bounced = true;
        if (bounced) apex = std::max(apex, b.position.y - half);
        if (bounced && b.linearVelocity.y < 0.0f) break;
    }
    ASSERT_TRUE(bounced);
    // The approach taken after the step's gravity would rise several per cent high, so the
    // bound is 0.5 %.
    EXPECT_NEAR(apex / (e * e * drop), 1.0, 5e-3) << "rebound " << apex << " m from " << drop;
    // Flat in, flat out: it does not tumble.
    EXPECT_LT(glm::length(world.body(box).angularVelocity), 0.05f);
}

TEST(Contacts, PerfectlyElasticBallLeavesAtItsArrivalSpeedAndReturnsToItsHeight) {
    // Restitution 1 at 60 Hz: in the step of contact the ball's velocity turns from -v to +v
    // (the stored speed it arrived with), and every rebound reaches the drop height again.
    World world = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "gravity": [0, -10, 0]},
      "materials": {"bouncy": {"friction": 0.5, "restitution": 1.0}},
      "shapes": {"ground": {"type": "plane"}, "ball": {"type": "sphere", "radius": 0.5}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "ball", "shape": "ball", "mass": 1, "position": [0, 1.5, 0],
                  "material": "bouncy"}]})");
    const std::uint32_t ball = 1;
    const float drop = 1.0f; // the ball's bottom starts 1 m up
    int bounces = 0;
    float last = 0.0f, apex = 0.0f;
    for (int i = 0; i < 600 && bounces < 4; ++i) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        const BodyState b = world.body(ball);
        const float v = b.linearVelocity.y;
        if (last < 0.0f && v > 0.0f) {
            EXPECT_NEAR(v, -last, 1e-5f * -last) << "bounce " << bounces;
            if (bounces > 0) {
                EXPECT_NEAR(apex, drop, 5e-3f * drop) << "rebound " << bounces;
            }
            ++bounces;
            apex = 0.0f;
        }
        apex = std::max(apex, b.position.y - 0.5f);
        last = v;
    }
    EXPECT_EQ(bounces, 4);
}

TEST(Contacts, FrictionAndRestitutionCombinePerContact) {
    // A bouncy ball on a dead floor bounces (the larger restitution); a slippery block on a rough
    // floor slides with sqrt(0.04 * 1.0) = 0.2.
    World world = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.004166667},
      "materials": {"rough": {"friction": 1.0}, "ice": {"friction": 0.04},
                    "rubber": {"friction": 0.5, "restitution": 0.8}},
      "shapes": {"ground": {"type": "plane"}, "ball": {"type": "sphere", "radius": 0.2},
                 "block": {"type": "box", "half_extents": [0.2, 0.2, 0.2]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true, "material": "rough"},
                 {"name": "ball", "shape": "ball", "mass": 1, "position": [5, 1.2, 0],
                  "material": "rubber"},
                 {"name": "block", "shape": "block", "mass": 1, "position": [0, 0.2, 0],
                  "linear_velocity": [3, 0, 0], "material": "ice"}]})");
    const std::uint32_t ball = 1, block = 2;
    float ballUp = 0.0f, ballDown = 0.0f, v0 = 0.0f, v1 = 0.0f;
    for (int i = 1; i <= 240; ++i) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        ballUp = std::max(ballUp, world.body(ball).linearVelocity.y);
        if (ballUp == 0.0f) ballDown = std::max(ballDown, -world.body(ball).linearVelocity.y);
        if (i == 24) v0 = world.body(block).linearVelocity.x;  // after 0.1 s of sliding
        if (i == 120) v1 = world.body(block).linearVelocity.x; // 0.4 s later
    }
    // The block slows at mu g, mu = sqrt(0.04 * 1.0).
    EXPECT_NEAR((v0 - v1) / 0.4f, 0.2f * 9.81f, 0.005f * 0.2f * 9.81f);
    // It hits at about sqrt(2 g 1 m) = 4.43 m/s (the last step's velocity before the contact,
    // within two steps of gravity) and leaves at 0.8 of that.
    EXPECT_NEAR(ballDown, std::sqrt(2.0f * 9.81f), 2.0f * 9.81f * 0.004166667f);
    EXPECT_NEAR(ballUp, 0.8f * ballDown, 1e-5f * ballDown);
}

// A ball dropped from 5.987 m at 60 Hz rebounds to e^2 of that within 1 mm: the approach speed
// before the step's gravity, carried to the contact, and the rebound leaving from it.
TEST(Contacts, ElasticBallReboundsToItsDropHeight) {
    World world = test::worldFromText(test::dropScene(1.0f));
    test::expectReboundHeight(world, 1.0f, 0.001f, 0.001f);
}
TEST(Contacts, HalfElasticBallReboundsToAQuarterOfItsDropHeight) {
    World world = test::worldFromText(test::dropScene(0.5f));
    test::expectReboundHeight(world, 0.5f, 0.001f, 0.001f);
}

TEST(Contacts, RestitutionThresholdIsHalfAMetrePerSecond) {
    World above = test::worldFromText(test::approachScene(0.75f));
    World below = test::worldFromText(test::approachScene(0.35f));
    test::expectRestitutionThreshold(above, below);
}

} // namespace
} // namespace rubble
