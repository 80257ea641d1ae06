// tests/physics/integrator_test.cpp: free fall, projectile, an undamped oscillator and a constant
// spin against closed forms, for symplectic and explicit Euler.
#include <numbers>

#include <gtest/gtest.h>

#include "support/physics_cases.h"
#include "support/test_util.h"

namespace rubble {
namespace {

std::string ballScene(const std::string& integrator, const std::string& velocity, float dt,
                      const std::string& gravity = "[0, -9.81, 0]") {
    return R"({"format": "rubble-scene", "version": 1,
      "simulation": {"dt": )" + std::to_string(dt) + R"(, "gravity": )" + gravity +
           R"(, "integrator": ")" + integrator + R"("},
      "shapes": {"ball": {"type": "sphere", "radius": 0.1}},
      "bodies": [{"name": "b", "shape": "ball", "mass": 2.0, "position": [1, 100, -2],
                  "linear_velocity": )" + velocity + "}]}";
}

// Symplectic Euler updates v then x, so after n steps v_n = v0 + n g dt and
// x_n = x0 + n dt v0 + g dt^2 n (n + 1) / 2; explicit Euler moves x first: n (n - 1) / 2.
glm::dvec3 discretePosition(glm::dvec3 x0, glm::dvec3 v0, glm::dvec3 g, double dt, int n,
                            bool symplectic) {
    const double k = symplectic ? n * (n + 1) / 2.0 : n * (n - 1) / 2.0;
    return x0 + double(n) * dt * v0 + g * dt * dt * k;
}

void checkProjectile(const std::string& integrator, glm::dvec3 v0) {
    const float dt = 1.0f / 240.0f;
    std::string velocity = "[";
    velocity += std::to_string(v0.x) + ", " + std::to_string(v0.y) + ", ";
    velocity += std::to_string(v0.z) + "]";
    World world = test::worldFromText(ballScene(integrator, velocity, dt));
    const glm::dvec3 x0(1, 100, -2), g(glm::vec3(0.0f, -9.81f, 0.0f));
    const double h = world.options().dt; // as the file spells it, rounded to float
    const int steps = 480;
    for (int i = 1; i <= steps; ++i) {
        ASSERT_TRUE(world.step().ok());
        if (i % 60 != 0) continue;
        const glm::dvec3 x(world.body(0).position);
        const glm::dvec3 exact = discretePosition(x0, v0, g, h, i, integrator == "symplectic");
        // The discrete solution, to float round-off.
        EXPECT_NEAR(glm::length(x - exact), 0.0, 2e-4) << integrator << " step " << i;
        // The continuous solution, within the method's O(dt) error g t dt / 2.
        const double t = i * h;
        const glm::dvec3 continuous = x0 + v0 * t + 0.5 * g * t * t;
        EXPECT_NEAR(glm::length(x - continuous), 0.5 * 9.81 * t * h, 3e-4);
        const glm::dvec3 v(world.body(0).linearVelocity);
        EXPECT_NEAR(glm::length(v - (v0 + g * t)), 0.0, 1e-4);
    }
}

TEST(Integrators, FreeFallMatchesSymplecticDiscreteSolution) { checkProjectile("symplectic", {0, 0, 0}); }
TEST(Integrators, FreeFallMatchesExplicitDiscreteSolution) { checkProjectile("explicit", {0, 0, 0}); }
TEST(Integrators, ProjectileMatchesSymplecticDiscreteSolution) { checkProjectile("symplectic", {3, 12, -1.5}); }
TEST(Integrators, ProjectileMatchesExplicitDiscreteSolution) { checkProjectile("explicit", {3, 12, -1.5}); }

TEST(Integrators, ProjectileLandsWhereTheParabolaSays) {
    // At 1 kHz the O(dt) error is below 1 cm over the flight.
    World world = test::worldFromText(ballScene("symplectic", "[4, 9.81, 0]", 0.001f));
    for (int i = 0; i < 2000; ++i) ASSERT_TRUE(world.step().ok());
    // Apex after 1 s at 100 + 9.81/2; back to launch height after 2 s, 8 m downrange.
    EXPECT_NEAR(world.body(0).position.y, 100.0f, 0.011f);
    EXPECT_NEAR(world.body(0).position.x, 1.0f + 8.0f, 1e-3f);
}

// Energy of a unit-mass body on a spring of stiffness k = (2 pi)^2 (period 1 s), no gravity.
double springEnergy(const World& w, double k) {
    const BodyState b = w.body(0);
    const double x = b.position.x, v = b.linearVelocity.x;
    return 0.5 * b.mass * v * v + 0.5 * k * x * x;
}

double oscillate(const std::string& integrator, int periods, double& maxRelativeError) {
    const double k = 4.0 * std::numbers::pi * std::numbers::pi;
    std::string scene = ballScene(integrator, "[0, 0, 0]", 0.01f, "[0, 0, 0]");
    scene.replace(scene.find("[1, 100, -2]"), 12, "[1, 0, 0]");
    scene.replace(scene.find("\"mass\": 2.0"), 11, "\"mass\": 1.0");
    World world = test::worldFromText(scene);
    const double e0 = springEnergy(world, k);
    maxRelativeError = 0.0;
    for (int i = 0; i < periods * 100; ++i) {
        world.addForce(0, glm::vec3(float(-k * world.body(0).position.x), 0.0f, 0.0f));
        EXPECT_TRUE(world.step().ok());
        maxRelativeError = std::max(maxRelativeError, std::abs(springEnergy(world, k) / e0 - 1.0));
    }
    return springEnergy(world, k) / e0;
}

TEST(Integrators, ExplicitEulerGainsEnergyOnAnOscillator) {
    double maxError = 0.0;
    // Each step multiplies the energy by 1 + (omega dt)^2: after 10 periods e^(1000 * 0.00395).
    const double ratio = oscillate("explicit", 10, maxError);
    EXPECT_GT(ratio, 40.0);
    EXPECT_LT(ratio, 70.0);
}

TEST(Integrators, SymplecticEulerKeepsOscillatorEnergyBounded) {
    double maxError = 0.0;
    const double ratio = oscillate("symplectic", 100, maxError);
    // The modified energy is conserved: the true energy oscillates by about omega dt / 2.
    EXPECT_LT(maxError, 0.04);
    EXPECT_NEAR(ratio, 1.0, 0.04);
}

// A ball spinning at a constant 10 rad/s turns by 10 rad in 1 s (tests/support/physics_cases.h).
TEST(Integrators, SymplecticSpinTurnsByOmegaTimesT) {
    World world = test::worldFromText(test::spinScene("symplectic"));
    test::expectSpinTurnsByOmegaTimesT(world);
}
TEST(Integrators, ExplicitSpinTurnsByOmegaTimesT) {
    World world = test::worldFromText(test::spinScene("explicit"));
    test::expectSpinTurnsByOmegaTimesT(world);
}

} // namespace
} // namespace rubble
