// tests/support/physics_cases.h: physics cases run on both backends: each is a scene (the
// simulation block's extra keys choose the device's collision and solver) and the check of its
// closed form on a World, used by tests/physics (CPU reference) and tests/gpu (OpenCL).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "rubble/world.h"

namespace rubble::test {

/// Unit crates in a block nx wide, ny high and nz deep on a floor, 0.99 m apart (each touching
/// its neighbours by 1 cm), named c<x * ny * nz + y * nz + z>; friction 0.5, 10 iterations.
inline std::string crateBlockScene(int nx, int ny, int nz) {
    std::string json = R"({"format": "rubble-scene", "version": 1, "name": "block",
      "simulation": {"dt": 0.016666667, "solver": {"iterations": 10}},
      "materials": {"default": {"friction": 0.5, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true})";
    for (int x = 0; x < nx; ++x)
        for (int y = 0; y < ny; ++y)
            for (int z = 0; z < nz; ++z)
                json += ", {\"name\": \"c" + std::to_string((x * ny + y) * nz + z) +
                        "\", \"shape\": \"crate\", \"mass\": 1, \"position\": [" +
                        std::to_string(x * 0.99) + ", " + std::to_string(0.495 + y * 0.99) +
                        ", " + std::to_string(z * 0.99) + "]}";
    return json + "]}";
}

/// The keys a device run adds to a scene's simulation block: particles and the Jacobi solver.
inline const char* kDeviceSimulation =
    R"(, "collision": {"method": "particles", "particle_spacing": 0.1},
       "solver": {"type": "jacobi", "iterations": 10})";

/// The keys a device run with SAT and PGS adds (every body on the device, the CPU's algorithms).
inline const char* kDeviceSatSimulation =
    R"(, "collision": {"method": "sat"}, "solver": {"type": "pgs", "iterations": 10})";

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
/// more than `sinking` m on the way. With the approach taken after the step's gravity and the
/// bounce taken where the step began, the rebound would rise well above e^2 h.
inline void expectReboundHeight(World& world, float e, float tolerance, float sinking) {
    const float h = 5.987f;
    const Rebound r = dropAndRebound(world);
    ASSERT_TRUE(r.bounced) << "e = " << e;
    EXPECT_NEAR(r.apex, e * e * h, tolerance) << "e = " << e << ": rebound from " << h << " m";
    EXPECT_GT(r.lowest, -sinking) << "e = " << e;
}

/// The sum of the dynamic bodies' linear momenta, kg m/s.
inline glm::dvec3 totalMomentum(const World& world) {
    glm::dvec3 p(0.0);
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i)
        if (!world.body(i).isStatic) p += glm::dvec3(world.body(i).linearMomentum);
    return p;
}

/// A row of five 1 kg unit boxes `gap` m apart (1 cm: centres at x = 0, 1.01, ..., 4.04) on a
/// frictionless floor, and a sixth, the striker, 2 m to their left sliding at 2 m/s toward them:
/// the row sleeps after half a second, the striker reaches it after one, restitution 0. With a
/// gap of 0 the boxes rest against each other and the hit has to reach through all five at once.
inline std::string sleepingRowScene(const std::string& simulation = "", double gap = 0.01) {
    std::string bodies = R"({"name": "floor", "shape": "ground", "static": true, "material": "ice"},
        {"name": "striker", "shape": "crate", "mass": 1.0, "position": [-3.0, 0.5, 0],
         "linear_velocity": [2, 0, 0], "material": "ice"})";
    for (int i = 0; i < 5; ++i)
        bodies += R"(, {"name": "row)" + std::to_string(i) +
                  R"(", "shape": "crate", "mass": 1.0, "material": "ice", "position": [)" +
                  std::to_string((1.0 + gap) * i) + ", 0.5, 0]}";
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667)" +
           simulation + R"(},
      "materials": {"ice": {"friction": 0.0, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane"},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [)" +
           bodies + "]}";
}

/// A column of sixteen 1 kg crates (1 m boxes, friction 0.5) on the floor, crate i at height
/// i + 0.5 m shifted along x by 0.03 i + 0.003 i^2 m: it leans and topples slowly, pivoting on
/// its base, whose lower crates move at a few cm/s for the first second (slower than the sleep
/// speeds) while the top moves at up to a metre a second.
inline std::string leaningColumnScene(const std::string& simulation = "") {
    std::string bodies = R"({"name": "floor", "shape": "ground", "static": true})";
    for (int i = 0; i < 16; ++i)
        bodies += R"(, {"name": "c)" + std::to_string(i) +
                  R"(", "shape": "crate", "mass": 1.0, "position": [)" +
                  std::to_string(0.03 * i + 0.003 * i * i) + ", " + std::to_string(0.5 + i) +
                  ", 0]}";
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "solver": {"type": "pgs", "iterations": 10})" +
           simulation + R"(},
      "materials": {"default": {"friction": 0.5, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane"},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [)" +
           bodies + "]}";
}

/// The touching row of sleepingRowScene (gap 0) with its first two boxes joined by a ball joint
/// at the middle of the faces they share: the hit wakes the pair as one joint group, and the
/// wake has to go on from the second box, which the striker does not touch.
inline std::string jointedRowScene(const std::string& simulation = "") {
    std::string scene = sleepingRowScene(simulation, 0.0);
    scene.insert(scene.rfind('}'), R"(, "joints": [{"type": "ball", "a": "row0", "b": "row1",
        "anchor": [0.5, 0.5, 0]}])");
    return scene;
}

/// The striker's 2 kg m/s stays in the bodies through its hit on the sleeping row (nothing
/// pushes sideways on a frictionless floor): within `tolerance` at every step for 3 s, and the
/// row moves. Meeting the row as a wall, the striker would stop and the momentum be gone.
inline void expectSleepingRowTakesTheHit(World& world, double tolerance) {
    ASSERT_TRUE(world.step().ok());
    for (int i = 0; i < 40; ++i) ASSERT_TRUE(world.step().ok());
    for (std::uint32_t i = 2; i < world.bodyCount(); ++i)
        ASSERT_TRUE(world.body(i).asleep) << world.bodyName(i) << " sleeps before the hit";
    double worst = 0.0;
    for (int i = 0; i < 180; ++i) {
        ASSERT_TRUE(world.step().ok());
        worst = std::max(worst, std::abs(totalMomentum(world).x - 2.0));
    }
    EXPECT_LT(worst, tolerance) << "kg m/s away from the striker's 2 kg m/s";
    EXPECT_GT(world.body(2).position.x, 0.1f) << "the first box of the row moves";
}

/// Two 1 kg balls (radius 0.2 m, restitution 1, frictionless) without gravity: one at rest at
/// the origin, asleep after half a second; the other 2.0125 m to its left at 1.5 m/s (2.5 cm a
/// step), reaching it after 1.075 s. The gap, 1.25 cm, is first within the contact margin (4 mm
/// and the step's 2.5 cm of approach) in the step that closes it: no earlier step sees it coming.
inline std::string cradleScene(const std::string& simulation = "") {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667, "gravity": [0, 0, 0])" +
           simulation + R"(},
      "materials": {"steel": {"friction": 0.0, "restitution": 1.0}},
      "shapes": {"ball": {"type": "sphere", "radius": 0.2}},
      "bodies": [{"name": "moving", "shape": "ball", "mass": 1.0, "position": [-2.0125, 0, 0],
                  "linear_velocity": [1.5, 0, 0], "material": "steel"},
                 {"name": "resting", "shape": "ball", "mass": 1.0, "position": [0, 0, 0],
                  "material": "steel"}]})";
}

/// Equal masses, e = 1, head on: the moving ball stops and the resting one leaves at 1.5 m/s
/// (momentum m v and energy m v^2 / 2 both kept), within `tolerance` m/s. Meeting the sleeping
/// ball as a wall, the moving one bounced back at -1.5 m/s and the other stayed.
inline void expectCradleExchange(World& world, float tolerance) {
    for (int i = 0; i < 40; ++i) ASSERT_TRUE(world.step().ok());
    ASSERT_TRUE(world.body(1).asleep) << "the resting ball sleeps before the hit";
    for (int i = 0; i < 80; ++i) ASSERT_TRUE(world.step().ok());
    EXPECT_NEAR(world.body(0).linearVelocity.x, 0.0f, tolerance) << "the moving ball stops";
    EXPECT_NEAR(world.body(1).linearVelocity.x, 1.5f, tolerance) << "the resting ball leaves";
}

/// The sleeping row of sleepingRowScene without the striker, and at t = 1 s an explosion 1.5 m
/// left of the first box, at its height, of 20 N s and 3 m reach: it reaches the first two
/// boxes (1.5 m and 2.51 m away) with 20 (1 - d / 3) N s straight along x.
inline std::string explodedRowScene(const std::string& simulation = "") {
    std::string scene = sleepingRowScene(simulation);
    const std::string striker = R"(,
        {"name": "striker", "shape": "crate", "mass": 1.0, "position": [-3.0, 0.5, 0],
         "linear_velocity": [2, 0, 0], "material": "ice"})";
    scene.replace(scene.find(striker), striker.size(), "");
    scene.insert(scene.rfind('}'), R"(, "events": [{"type": "explosion", "time": 1.0,
        "centre": [-1.5, 0.5, 0], "impulse": 20, "radius": 3}])");
    return scene;
}

/// The explosion's impulses, sum of 20 (1 - d / 3) over the boxes it reaches, stay in the bodies
/// (within `tolerance` kg m/s at every step for 2 s after it): a sleeping box the blown ones hit
/// takes its share. Met as walls, the sleeping boxes kept it.
inline void expectExplodedRowKeepsItsMomentum(World& world, double tolerance) {
    double expected = 0.0;
    for (int i = 0; i < 5; ++i) {
        const double d = 1.5 + 1.01 * i;
        if (d < 3.0) expected += 20.0 * (1.0 - d / 3.0);
    }
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(world.step().ok()); // the explosion is the next step
    for (std::uint32_t i = 1; i < world.bodyCount(); ++i)
        ASSERT_TRUE(world.body(i).asleep) << world.bodyName(i) << " sleeps before the explosion";
    double worst = 0.0;
    for (int i = 0; i < 120; ++i) {
        ASSERT_TRUE(world.step().ok());
        worst = std::max(worst, std::abs(totalMomentum(world).x - expected));
    }
    EXPECT_LT(worst, tolerance) << "kg m/s away from the explosion's " << expected;
    EXPECT_GT(world.body(5).position.x, 4.04f + 0.1f) << "the last box of the row moves";
}

/// Unit boxes stacked on a floor (friction 0.5), box i of mass masses[i] with its centre at
/// i + 0.5 m, the resting height; 60 Hz, 10 iterations (the defaults).
inline std::string massStackScene(const std::vector<double>& masses,
                                  const std::string& simulation = "") {
    std::string bodies = R"({"name": "floor", "shape": "ground", "static": true})";
    for (std::size_t i = 0; i < masses.size(); ++i) {
        char body[160];
        std::snprintf(
            body, sizeof body,
            R"(, {"name": "b%zu", "shape": "crate", "mass": %.9g, "position": [0, %g, 0]})", i,
            masses[i], double(i) + 0.5);
        bodies += body;
    }
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": 0.016666667)" +
           simulation + R"(},
      "shapes": {"ground": {"type": "plane"}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [)" +
           bodies + "]}";
}

/// Ten 1 kg unit boxes stacked on a floor (friction 0.5), asleep after a second, and a 0.2 kg
/// pebble (0.4 m a side) dropped from 25 m that lands on the top box at about 13 m/s in step 104.
inline std::string pebbleOnStackScene(const std::string& simulation = "") {
    std::string scene = massStackScene(std::vector<double>(10, 1.0), simulation);
    scene.replace(scene.find(R"("crate": {)"), 0,
                  R"("pebble": {"type": "box", "half_extents": [0.2, 0.2, 0.2]}, )");
    scene.insert(scene.rfind(']'), R"(, {"name": "pebble", "shape": "pebble", "mass": 0.2,
        "position": [0.1, 25.0, 0.05]})");
    return scene;
}

/// The largest sag of any box of pebbleOnStackScene below where it slept, over the second after
/// the pebble lands, and the pebble's downward speed two steps after it lands.
struct PebbleHit {
    float sag = 0.0f, pebbleSpeed = 0.0f;
};
inline PebbleHit pebbleHit(World& world) {
    const std::uint32_t pebble = world.bodyCount() - 1;
    PebbleHit hit;
    for (int step = 0; step < 103; ++step) EXPECT_TRUE(world.step().ok());
    std::vector<float> rest;
    for (std::uint32_t i = 1; i < pebble; ++i) {
        EXPECT_TRUE(world.body(i).asleep) << world.bodyName(i) << " sleeps before the hit";
        rest.push_back(world.body(i).position.y);
    }
    EXPECT_GT(world.body(pebble).position.y, 10.3f) << "the pebble has not landed yet";
    for (int step = 0; step < 60; ++step) {
        EXPECT_TRUE(world.step().ok());
        for (std::uint32_t i = 1; i < pebble; ++i)
            hit.sag = std::max(hit.sag, rest[i - 1] - world.body(i).position.y);
        if (step == 2) hit.pebbleSpeed = -world.body(pebble).linearVelocity.y;
    }
    return hit;
}

/// For 10 s every box of the mass stack stays within `down` of its resting height (i + 0.5 m)
/// and `sideways` of the axis it started on, and then the whole stack sleeps.
inline void expectStackStands(World& world, float down, float sideways) {
    ASSERT_EQ(world.options().solver.iterations, 10);
    float worstDown = 0.0f, worstSideways = 0.0f;
    for (int step = 0; step < 600; ++step) {
        ASSERT_TRUE(world.step().ok());
        for (std::uint32_t i = 1; i < world.bodyCount(); ++i) {
            const glm::vec3 p = world.body(i).position;
            worstDown = std::max(worstDown, float(i) - 0.5f - p.y);
            worstSideways = std::max(worstSideways, std::hypot(p.x, p.z));
        }
    }
    std::printf("[ stack ] %.4f m below the resting heights, %.4f m off the axis at worst\n",
                double(worstDown), double(worstSideways));
    EXPECT_LT(worstDown, down) << "m below the resting heights";
    EXPECT_LT(worstSideways, sideways) << "m off the stack's axis";
    for (std::uint32_t i = 1; i < world.bodyCount(); ++i)
        EXPECT_TRUE(world.body(i).asleep) << world.bodyName(i) << " settles";
}

} // namespace rubble::test
