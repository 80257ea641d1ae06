// tests/support/physics_cases.h: physics cases run on both backends: each is a scene (the
// simulation block's extra keys choose the device's collision and solver) and the check of its
// closed form on a World, used by tests/physics (CPU reference) and tests/gpu (OpenCL).
#pragma once

#include <cmath>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "rubble/world.h"

namespace rubble::test {

/// The keys a device run adds to a scene's simulation block: particles and the Jacobi solver.
inline const char* kDeviceSimulation =
    R"(, "collision": {"method": "particles", "particle_spacing": 0.1},
       "solver": {"type": "jacobi", "iterations": 10})";

/// A free ball spinning at 10 rad/s about (1, 2, 2)/3 in the world (a sphere: its angular
/// velocity stays constant), 60 Hz, no gravity.
inline std::string spinScene(const std::string& integrator, const std::string& simulation = "") {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "gravity": [0, 0, 0], "integrator": ")" +
           integrator + "\"" + simulation + R"(},
      "shapes": {"ball": {"type": "sphere", "radius": 0.2}},
      "bodies": [{"name": "b", "shape": "ball", "mass": 1.0,
                  "angular_velocity": [3.3333333, 6.6666667, 6.6666667]}]})";
}

/// Steps the spin scene for 1 s: after n steps the orientation is the turn by 10 n dt about the
/// axis, to float round-off (1e-5 rad). The first-order update normalise(q + dt/2 (w, 0) q)
/// turns 2 atan(w dt / 2) per step: 9.977 rad after 1 s, 0.023 rad short.
inline void expectSpinTurnsByOmegaTimesT(World& world) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(1.0, 2.0, 2.0));
    const double omega = 10.0, h = world.options().dt;
    for (int i = 1; i <= 60; ++i) {
        ASSERT_TRUE(world.step().ok());
        const double angle = omega * h * i; // 10 rad after 60 steps
        const glm::dquat expected = glm::angleAxis(angle, axis);
        // The angle of the turn between them, from the vector part of q expected^-1 (acos of
        // their dot product would read a float quaternion's round-off in its norm as an angle).
        const glm::dquat r =
            glm::normalize(glm::dquat(world.body(0).orientation)) * glm::conjugate(expected);
        const double error =
            2.0 * std::atan2(glm::length(glm::dvec3(r.x, r.y, r.z)), std::abs(r.w));
        ASSERT_LT(error, 1e-5) << "step " << i << ": expected a turn of " << angle << " rad";
    }
    EXPECT_NEAR(glm::length(glm::dvec3(world.body(0).angularVelocity)), omega, 1e-4);
}

/// A ball (radius 0.2 m, restitution 1, as the floor's) whose bottom starts 0.3 m above a floor,
/// moving down at `speed` m/s, without gravity, 60 Hz.
inline std::string approachScene(float speed, const std::string& simulation = "") {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "gravity": [0, 0, 0])" +
           simulation + R"(},
      "materials": {"elastic": {"friction": 0.5, "restitution": 1.0}},
      "shapes": {"ground": {"type": "plane"}, "ball": {"type": "sphere", "radius": 0.2}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true, "material": "elastic"},
                 {"name": "ball", "shape": "ball", "mass": 1.0, "position": [0, 0.5, 0],
                  "linear_velocity": [0, )" +
           std::to_string(-speed) + R"(, 0], "material": "elastic"}]})";
}

/// The ball's largest upward speed over 2 s of the approach scene, m/s.
inline float reboundSpeed(World& world) {
    float up = 0.0f;
    for (int i = 0; i < 120; ++i) {
        EXPECT_TRUE(world.step().ok());
        up = std::max(up, world.body(1).linearVelocity.y);
    }
    return up;
}

/// Above the threshold (0.75 m/s) the ball leaves at e times its approach speed; below it (0.35
/// m/s) it stops on the floor: RUBBLE_RESTITUTION_THRESHOLD = 0.5 m/s on every backend.
inline void expectRestitutionThreshold(World& above, World& below) {
    EXPECT_NEAR(reboundSpeed(above), 0.75f, 0.05f) << "an approach at 0.75 m/s bounces";
    EXPECT_LT(reboundSpeed(below), 0.05f) << "an approach at 0.35 m/s does not";
}

/// A ball (radius 0.5 m, 1 kg, restitution e; the floor's is 0) whose bottom starts 5.987 m above
/// the floor, at rest, 60 Hz.
inline std::string dropScene(float e, const std::string& simulation = "") {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667)" +
           simulation + R"(},
      "materials": {"ball": {"friction": 0.5, "restitution": )" +
           std::to_string(e) + R"(}},
      "shapes": {"ground": {"type": "plane"}, "ball": {"type": "sphere", "radius": 0.5}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "ball", "shape": "ball", "mass": 1.0, "position": [0, 6.487, 0],
                  "material": "ball"}]})";
}

/// What a drop did: the highest point of the ball's bottom after its first bounce, and the lowest
/// before it, m above the floor.
struct Rebound {
    float apex = 0.0f, lowest = 1e9f;
    bool bounced = false;
};

/// Steps the drop scene until the ball turns down after its first bounce (at most 6 s).
inline Rebound dropAndRebound(World& world) {
    Rebound r;
    for (int i = 0; i < 360; ++i) {
        EXPECT_TRUE(world.step().ok());
        const BodyState b = world.body(1);
        const float bottom = b.position.y - 0.5f;
        if (!r.bounced) r.lowest = std::min(r.lowest, bottom);
        if (b.linearVelocity.y > 0.0f) r.bounced = true;
        if (r.bounced) r.apex = std::max(r.apex, bottom);
        if (r.bounced && b.linearVelocity.y < 0.0f) break;
    }
    return r;
}

/// The rebound of a drop from h = 5.987 m rises to e^2 h (energy e^2 of the impact's, the rebound
/// leaving from the contact) within `tolerance` m, and the ball does not sink into the floor by
/// more than `sinking` m on the way. With the approach measured after the step's gravity and the
/// bounce taken where the step began, e = 1 rose to 6.167 m and e = 0.5 to 1.671 m instead of
/// 1.497 m.
inline void expectReboundHeight(World& world, float e, float tolerance, float sinking) {
    const float h = 5.987f;
    const Rebound r = dropAndRebound(world);
    ASSERT_TRUE(r.bounced) << "e = " << e;
    EXPECT_NEAR(r.apex, e * e * h, tolerance) << "e = " << e << ": rebound from " << h << " m";
    EXPECT_GT(r.lowest, -sinking) << "e = " << e;
}

} // namespace rubble::test
