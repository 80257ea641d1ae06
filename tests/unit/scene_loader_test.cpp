// tests/unit/scene_loader_test.cpp: host/scene: defaults, generators, references, overrides.
#include <gtest/gtest.h>

#include "host/scene/generators.h"
#include "support/test_util.h"

namespace rubble {
namespace {

Scene parse(const std::string& text) {
    Result<Scene> s = parseScene(text, "t.json", ".");
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().describe());
    return s.ok() ? *s : Scene{};
}

TEST(SceneLoader, DefaultsMatchTheFormat) {
    const Scene s = parse(R"({"format": "rubble-scene", "version": 1})");
    EXPECT_EQ(s.name, "t");
    EXPECT_FLOAT_EQ(s.simulation.dt, 1.0f / 60.0f);
    EXPECT_EQ(s.simulation.steps, 600);
    EXPECT_EQ(s.simulation.gravity, glm::vec3(0.0f, -9.81f, 0.0f));
    EXPECT_EQ(s.simulation.integrator, Integrator::Symplectic);
    EXPECT_EQ(s.simulation.backend, Backend::Cpu);
    EXPECT_EQ(s.simulation.collisionMethod(), CollisionMethod::Sat);
    EXPECT_FLOAT_EQ(s.simulation.collision.particleSpacing, 0.1f);
    EXPECT_FALSE(s.simulation.solver.type.has_value());
    EXPECT_EQ(s.simulation.solverType(), SolverType::Pgs);
    EXPECT_EQ(s.simulation.solver.iterations, 10);
    EXPECT_FLOAT_EQ(s.simulation.solver.baumgarte, 0.2f);
    EXPECT_FLOAT_EQ(s.simulation.solver.slop, 0.005f);
    EXPECT_FLOAT_EQ(s.simulation.solver.relaxation, 1.0f);
    EXPECT_TRUE(s.simulation.solver.warmStart);
    EXPECT_EQ(s.simulation.coupling, Coupling::OneWay);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "default");
    EXPECT_FLOAT_EQ(s.materials[0].friction, 0.5f);
    EXPECT_FLOAT_EQ(s.materials[0].restitution, 0.0f);
}

// On opencl a scene that names no collision method collides with particles (the scene format's
// contract), and one that names no solver solves them with pgs, as everywhere; naming sat gives
// SAT, with pgs its solver; a solver named is kept.
TEST(SceneLoader, OpenClBackendDefaultsToParticlesWithPgs) {
    const Scene s = parse(R"({"format": "rubble-scene", "version": 1,
        "simulation": {"backend": "opencl"}})");
    EXPECT_EQ(s.simulation.collisionMethod(), CollisionMethod::Particles);
    EXPECT_EQ(s.simulation.solverType(), SolverType::Pgs);
    const Scene sat = parse(R"({"format": "rubble-scene", "version": 1,
        "simulation": {"backend": "opencl", "collision": {"method": "sat"}}})");
    EXPECT_EQ(sat.simulation.collisionMethod(), CollisionMethod::Sat);
    EXPECT_EQ(sat.simulation.solverType(), SolverType::Pgs);
    const Scene named = parse(R"({"format": "rubble-scene", "version": 1,
        "simulation": {"backend": "opencl", "solver": {"type": "lcp-jacobi"}}})");
    EXPECT_EQ(named.simulation.collisionMethod(), CollisionMethod::Particles);
    EXPECT_EQ(named.simulation.solverType(), SolverType::LcpJacobi);
    const Scene cpu = parse(R"({"format": "rubble-scene", "version": 1,
        "simulation": {"collision": {"method": "particles"}}})");
    EXPECT_EQ(cpu.simulation.solverType(), SolverType::Pgs);
}

TEST(SceneLoader, GridGeneratorNamesAndOrdersXFastest) {
    const Scene s = parse(R"({"format": "rubble-scene", "version": 1,
      "shapes": {"c": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "first", "shape": "c", "mass": 1}],
      "generators": [{"type": "grid", "shape": "c", "density": 2, "count": [3, 2, 2],
                      "origin": [1, 2, 3], "spacing": [1.5, 2, 2.5], "name_prefix": "d"}]})");
    ASSERT_EQ(s.bodies.size(), 13u);
    EXPECT_EQ(s.bodies[0].name, "first");
    EXPECT_EQ(s.bodies[1].name, "d0");
    EXPECT_EQ(s.bodies[12].name, "d11");
    EXPECT_EQ(s.bodies[1].position, glm::vec3(1, 2, 3));
    EXPECT_EQ(s.bodies[2].position, glm::vec3(2.5f, 2, 3));    // x first
    EXPECT_EQ(s.bodies[4].position, glm::vec3(1, 4, 3));       // then y
    EXPECT_EQ(s.bodies[7].position, glm::vec3(1, 2, 5.5f));    // then z
    EXPECT_FLOAT_EQ(*s.bodies[5].density, 2.0f);
    // No jitter: identity orientation.
    EXPECT_EQ(s.bodies[5].orientation, glm::quat(1, 0, 0, 0));
}

TEST(SceneLoader, RotationJitterIsSeededAndBounded) {
    const std::vector<glm::quat> a = jitterRotations(7, 500, 0.1f);
    const std::vector<glm::quat> b = jitterRotations(7, 500, 0.1f);
    const std::vector<glm::quat> c = jitterRotations(8, 500, 0.1f);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    float largest = 0.0f;
    for (const glm::quat& q : a) {
        const float angle = 2.0f * std::acos(std::min(1.0f, std::abs(q.w)));
        EXPECT_LE(angle, 0.1f + 1e-5f);
        largest = std::max(largest, angle);
    }
    EXPECT_GT(largest, 0.09f); // the draws cover the range
}

TEST(SceneLoader, QuaternionsAreNormalisedAndReadAsWxyz) {
    const Scene s = parse(R"({"format": "rubble-scene", "version": 1,
      "shapes": {"c": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "b", "shape": "c", "mass": 1, "orientation": [2, 0, 2, 0]}]})");
    const glm::quat q = s.bodies[0].orientation;
    EXPECT_NEAR(q.w, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(q.y, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(q.x, 0.0f, 1e-7f);
}

TEST(SceneLoader, MaterialsAndReferencesResolve) {
    const Scene s = parse(R"({"format": "rubble-scene", "version": 1,
      "materials": {"default": {"friction": 0.8}, "ice": {"friction": 0.02, "restitution": 0.1}},
      "shapes": {"c": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "a", "shape": "c", "mass": 1},
                 {"name": "b", "shape": "c", "mass": 1, "material": "ice"}],
      "joints": [{"type": "hinge", "a": "a", "b": "b", "anchor": [0, 1, 0], "axis": [0, 0, 3]}]})");
    EXPECT_FLOAT_EQ(s.materials[0].friction, 0.8f);
    EXPECT_EQ(s.bodies[0].material, 0u);
    EXPECT_EQ(s.materials[s.bodies[1].material].name, "ice");
    ASSERT_EQ(s.joints.size(), 1u);
    EXPECT_EQ(s.joints[0].b, 1u);
    EXPECT_EQ(s.joints[0].axis, glm::vec3(0, 0, 1)); // normalised
}

TEST(SceneLoader, WorldUsesMassOrDensity) {
    World w = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "shapes": {"c": {"type": "box", "half_extents": [0.5, 1.0, 1.5]}},
      "bodies": [{"name": "m", "shape": "c", "mass": 3},
                 {"name": "d", "shape": "c", "density": 10}]})");
    EXPECT_FLOAT_EQ(w.body(0).mass, 3.0f);
    EXPECT_FLOAT_EQ(w.body(1).mass, 60.0f); // 1 x 2 x 3 m^3 at 10 kg/m^3
}

TEST(SceneLoader, InitialVelocitiesBecomeMomenta) {
    World w = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "shapes": {"c": {"type": "box", "half_extents": [0.5, 1.0, 1.5]}},
      "bodies": [{"name": "m", "shape": "c", "mass": 3, "orientation": [0.7071068, 0, 0, 0.7071068],
                  "linear_velocity": [1, 2, 3], "angular_velocity": [0, 0, 2]}]})");
    const BodyState b = w.body(0);
    EXPECT_NEAR(b.linearMomentum.y, 6.0f, 1e-6f);
    // About world z, which is the body's z: I_zz = m/3 (a^2 + b^2) = 1.25.
    EXPECT_NEAR(b.angularMomentum.z, 2.5f, 1e-5f);
    EXPECT_NEAR(b.angularVelocity.z, 2.0f, 1e-5f);
}

} // namespace
} // namespace rubble
