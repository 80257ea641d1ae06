// tests/physics/soft_step_test.cpp: the soft-step solver against closed forms and plain
// expectations: a box at rest without jitter, a stack of ten, a bounce's height and speed, a box
// landing flat without spin, friction on slopes, a pendulum's period on a ball joint, 1000 kg on
// 1 kg at its springs' overlap.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "physics/physics_util.h"
#include "support/physics_cases.h"
#include "support/test_util.h"

namespace rubble {
namespace {

const std::string kSoft = R"(, "solver": {"type": "soft-step"})";

// A shipped scene stepped with the soft step.
World softWorld(const std::string& file) {
    Scene scene = test::shippedScene(file);
    scene.simulation.solver.type = SolverType::SoftStep;
    return test::makeWorld(scene);
}

TEST(SoftStep, BoxAtRestHasNoJitter) {
    World world = softWorld("box_rest.json");
    const std::uint32_t box = *world.findBody("box");
    const glm::vec3 start = world.body(box).position;
    const int steps = int(std::lround(2.0 / world.options().dt));
    float drift = 0.0f, lateSpeed = 0.0f;
    for (int i = 0; i < steps; ++i) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        const BodyState b = world.body(box);
        drift = std::max(drift, glm::length(b.position - start));
        // The second second: the box has settled on its contacts.
        if (i >= steps / 2)
            lateSpeed = std::max(lateSpeed, glm::length(b.linearVelocity) +
                                                0.5f * glm::length(b.angularVelocity));
    }
    EXPECT_LT(lateSpeed, 1e-3f) << "m/s after the first second";
    EXPECT_LT(drift, 0.002f) << "m from where it was placed";
}

// Ten unit boxes stand for 10 s: none leaves its column by more than 2 cm or sinks by more than
// 4 cm (the contact springs carrying the boxes above give 1.6 cm at the top), and the stack
// sleeps.
TEST(SoftStep, StackOfTenStands) {
    World world = softWorld("stack_10.json");
    std::vector<glm::vec3> start = test::positionsOf(world);
    float sideways = 0.0f, down = 0.0f;
    for (int step = 0; step < 600; ++step) {
        ASSERT_TRUE(test::stepWorld(world, 1));
        for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
            const glm::vec3 d = world.body(i).position - start[i];
            sideways = std::max(sideways, std::hypot(d.x, d.z));
            down = std::max(down, -d.y);
        }
    }
    EXPECT_LT(sideways, 0.02f);
    EXPECT_LT(down, 0.04f);
    std::uint32_t asleep = 0;
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) asleep += world.body(i).asleep ? 1 : 0;
    EXPECT_EQ(asleep, world.bodyCount() - 1) << "everything but the floor settles";
}

// Restitution after the substeps with the approach before the step: the rebound rises to e^2 h.
TEST(SoftStep, BounceRisesToRestitutionSquaredHeight) {
    for (const float e : {0.5f, 0.8f}) {
        World world = test::worldFromText(test::dropScene(e, kSoft));
        test::expectReboundHeight(world, e, 0.03f * e * e * 5.987f, 0.05f);
    }
}

// A ball with restitution 1 leaves the floor in the step of contact at the speed it arrived
// with (restitution from the normal speed before the step, after the substeps): the step that
// turns it ends with the ball on the floor, neither short of it nor in it.
TEST(SoftStep, ElasticBallLeavesAtItsArrivalSpeed) {
    World world = test::worldFromText(test::dropScene(1.0f, kSoft));
    float arrival = 0.0f;
    for (int i = 0; i < 120; ++i) {
        ASSERT_TRUE(world.step().ok());
        const float vy = world.body(1).linearVelocity.y;
        if (vy < 0.0f) {
            arrival = -vy;
            continue;
        }
        ASSERT_GT(arrival, 10.0f) << "it fell about 6 m before the bounce";
        EXPECT_NEAR(vy, arrival, 1e-4f * arrival) << "m/s up after " << arrival << " m/s down";
        const float bottom = world.body(1).position.y - 0.5f;
        EXPECT_NEAR(bottom, 0.0f, 1e-3f) << "m above the floor in the step that turns it";
        return;
    }
    FAIL() << "no bounce in 2 s";
}

// A 1 kg unit box, faces level, whose bottom starts `height` m above the floor (friction 0.6,
// restitution 0, 60 Hz, no sleep), under `gravity` m/s^2.
std::string boxDropScene(double height, double gravity) {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "sleep": false, "gravity": [0, )" +
           std::to_string(-gravity) + R"(, 0], "solver": {"type": "soft-step"}},
      "materials": {"default": {"friction": 0.6, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane"},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "box", "shape": "crate", "mass": 1.0, "position": [0, )" +
           std::to_string(0.5 + height) + R"(, 0]}]})";
}

// A box that lands flat on its speculative contact stays without spin: all four corners of its
// face stop it together, though one pass over the points alone would give the first corner the
// most and turn the box (0.3-0.9 rad/s). At 10 m/s^2 the 2 m drop closes its gap in the last
// substep of the landing step, whose impulse the next step must not warm-start.
TEST(SoftStep, BoxLandingFlatDoesNotSpin) {
    for (const double gravity : {9.81, 10.0}) {
        for (const double height : {2.0, 4.0, 10.0}) {
            World world = test::worldFromText(boxDropScene(height, gravity));
            const std::uint32_t box = *world.findBody("box");
            bool landed = false;
            float spin = 0.0f;
            for (int i = 0; i < 180; ++i) {
                ASSERT_TRUE(test::stepWorld(world, 1));
                const BodyState b = world.body(box);
                landed = landed || b.position.y < 0.55f;
                if (landed) spin = std::max(spin, glm::length(b.angularVelocity));
            }
            ASSERT_TRUE(landed) << height << " m";
            EXPECT_LT(spin, 0.01f)
                << "rad/s after landing from " << height << " m at " << gravity << " m/s^2";
        }
    }
}

double slopeAngle(const World& world) {
    const glm::quat q = world.body(*world.findBody("ramp")).orientation;
    return 2.0 * std::atan2(double(q.z), double(q.w));
}

double downhillSpeed(const World& world, double angle) {
    const glm::dvec3 downhill(-std::cos(angle), -std::sin(angle), 0.0);
    return glm::dot(glm::dvec3(world.body(*world.findBody("box")).linearVelocity), downhill);
}

TEST(SoftStep, BoxBelowFrictionAngleSticks) {
    World world = softWorld("slope_below_friction.json");
    ASSERT_LT(std::tan(slopeAngle(world)), 0.5);
    const std::uint32_t box = *world.findBody("box");
    const glm::vec3 start = world.body(box).position;
    ASSERT_TRUE(test::stepWorld(world, 180));
    EXPECT_LT(glm::length(world.body(box).position - start), 0.002f);
}

TEST(SoftStep, BoxAboveFrictionAngleSlidesWithCoulombAcceleration) {
    World world = softWorld("slope_above_friction.json");
    const double angle = slopeAngle(world), mu = 0.5;
    ASSERT_GT(std::tan(angle), mu);
    ASSERT_TRUE(test::stepWorld(world, 12));
    const double v0 = downhillSpeed(world, angle), t0 = world.time();
    ASSERT_TRUE(test::stepWorld(world, 60));
    const double a = (downhillSpeed(world, angle) - v0) / (world.time() - t0);
    const double expected = 9.81 * (std::sin(angle) - mu * std::cos(angle));
    EXPECT_NEAR(a / expected, 1.0, 0.01) << "a = " << a << " m/s^2, expected " << expected;
    EXPECT_LT(glm::length(world.body(*world.findBody("box")).angularVelocity), 0.05f);
}

// A 1 m pendulum on a ball joint released at 10 degrees swings with the simple pendulum's period
// (corrected for amplitude) within 1 %, and its soft rod stretches by less than 2 mm.
TEST(SoftStep, PendulumOnABallJointKeepsItsPeriod) {
    const double theta = 10.0 * std::numbers::pi / 180.0;
    const std::string scene = R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667)" +
                              kSoft + R"(},
      "shapes": {"pin": {"type": "sphere", "radius": 0.02}, "bob": {"type": "sphere", "radius": 0.02}},
      "bodies": [{"name": "pivot", "shape": "pin", "static": true, "position": [0, 2, 0]},
                 {"name": "bob", "shape": "bob", "mass": 1.0, "position": [)" +
                              std::to_string(std::sin(theta)) + ", " +
                              std::to_string(2.0 - std::cos(theta)) + R"(, 0]}],
      "joints": [{"type": "ball", "a": "pivot", "b": "bob", "anchor": [0, 2, 0]}]})";
    World world = test::worldFromText(scene);
    std::vector<double> crossings;
    double lastX = world.body(1).position.x, lastT = 0.0;
    float stretch = 0.0f;
    for (int i = 0; i < 720; ++i) {
        ASSERT_TRUE(world.step().ok());
        const BodyState b = world.body(1);
        const double x = b.position.x, t = world.time();
        if (lastX > 0.0 && x <= 0.0) crossings.push_back(lastT + (t - lastT) * lastX / (lastX - x));
        lastX = x;
        lastT = t;
        stretch = std::max(stretch, std::abs(glm::length(b.position - glm::vec3(0, 2, 0)) - 1.0f));
    }
    ASSERT_GE(crossings.size(), 5u);
    const double period = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
    const double expected =
        2.0 * std::numbers::pi * std::sqrt(1.0 / 9.81) * (1.0 + theta * theta / 16.0);
    EXPECT_NEAR(period / expected, 1.0, 0.01) << "period " << period << " s";
    EXPECT_LT(stretch, 2e-3f) << "m of stretch";
}

// 1000 kg on 1 kg: the soft contacts give like springs of stiffness m_eff omega^2, m_eff the
// points' effective masses summed (the light box's 1 kg against the floor; 1 / (1/1 + 1/1000)
// kg between the boxes), at twice the contact hertz against the floor. The stack rests where
// the springs carry the weights, leaning by a few centimetres, and stays there.
TEST(SoftStep, ThousandToOneHeavyOnLightRestsAtItsSpringsOverlap) {
    World world = test::worldFromText(test::massStackScene({1.0, 1000.0}, kSoft));
    const SolverOptions& o = world.options().solver;
    const double g = 9.81, light = 1.0, heavy = 1000.0;
    const double omega = 2.0 * std::numbers::pi * o.contactHertz;
    const double floorSink = (light + heavy) * g / (light * 4.0 * omega * omega);
    const double boxSink = heavy * g / (1.0 / (1.0 / light + 1.0 / heavy) * omega * omega);
    float sideways = 0.0f, lateSpeed = 0.0f;
    for (int step = 0; step < 600; ++step) {
        ASSERT_TRUE(world.step().ok());
        for (std::uint32_t i = 1; i < 3; ++i) {
            const BodyState b = world.body(i);
            sideways = std::max(sideways, std::hypot(b.position.x, b.position.z));
            if (step >= 300) lateSpeed = std::max(lateSpeed, glm::length(b.linearVelocity));
        }
    }
    EXPECT_NEAR(0.5 - world.body(1).position.y, floorSink, 0.1 * floorSink);
    EXPECT_NEAR(1.5 - world.body(2).position.y, floorSink + boxSink, 0.1 * (floorSink + boxSink));
    EXPECT_LT(sideways, 0.1f) << "m off the stack's axis";
    EXPECT_LT(lateSpeed, 0.01f) << "m/s in the last 5 s";
}

// Two stacks of three boxes dropped 0.2 m onto the floor 6 m apart (two islands, landing faces),
// as the soft step runs them island by island, and with a pair of jointed balls falling far
// above, which makes it run every contact in one group: the boxes' trajectories are the same to
// the bit, since islands share no moving body.
TEST(SoftStep, IslandsAloneGiveTheBitsOfOneGroup) {
    std::string bodies = R"({"name": "floor", "shape": "ground", "static": true})";
    for (const float x : {-3.0f, 3.0f})
        for (int k = 0; k < 3; ++k)
            bodies += R"(, {"name": "b)" + std::to_string(int(x)) + "_" + std::to_string(k) +
                      R"(", "shape": "box", "mass": 1.0, "position": [)" + std::to_string(x) +
                      ", " + std::to_string(0.7f + 1.05f * float(k)) + ", " +
                      std::to_string(0.1f * float(k)) + "]}";
    const auto scene = [&](bool jointed) {
        std::string extra, joints;
        if (jointed) {
            extra = R"(, {"name": "j0", "shape": "ball", "mass": 1.0, "position": [0, 50, 0]},
                         {"name": "j1", "shape": "ball", "mass": 1.0, "position": [0, 48, 0]})";
            joints =
                R"(, "joints": [{"type": "ball", "a": "j0", "b": "j1", "anchor": [0, 49, 0]}])";
        }
        return R"({"format": "rubble-scene", "version": 1,
          "simulation": {"dt": 0.016666667, "sleep": false)" +
               kSoft + R"(},
          "shapes": {"ground": {"type": "plane"}, "box": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                     "ball": {"type": "sphere", "radius": 0.5}},
          "bodies": [)" +
               bodies + extra + "]" + joints + "}";
    };
    World alone = test::worldFromText(scene(false));
    World grouped = test::worldFromText(scene(true));
    const std::uint32_t boxes = alone.bodyCount();
    bool touched = false;
    for (int step = 0; step < 90; ++step) {
        ASSERT_TRUE(test::stepWorld(alone, 1));
        ASSERT_TRUE(test::stepWorld(grouped, 1));
        for (std::uint32_t i = 1; i < boxes; ++i) {
            const BodyState a = alone.body(i), b = grouped.body(i);
            ASSERT_EQ(a.position, b.position) << "body " << i << " step " << step;
            ASSERT_EQ(a.orientation, b.orientation) << "body " << i << " step " << step;
            ASSERT_EQ(a.linearVelocity, b.linearVelocity) << "body " << i << " step " << step;
            touched = touched || a.position.y < 0.51f;
        }
    }
    EXPECT_TRUE(touched) << "the bottom boxes landed";
}

} // namespace
} // namespace rubble
