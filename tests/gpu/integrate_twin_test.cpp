// tests/gpu/integrate_twin_test.cpp: OpenCL stages 1 and 6 (integrateVelocities,
// integratePositions) and absorbVelocityChange against their CPU twins on one input; a world
// without contacts stepped on both backends writes the same trajectory.
#include <random>

#include "gpu_fixture.h"
#include "host/gpu/integrate.h"
#include "host/core/integrate.h"
#include "host/core/math.h"

namespace rubble {
namespace {

using namespace shared;

// 101 tumbling bodies of three shapes (not a multiple of the work-group size), one static, 20 m
// apart: they fly in parallel and never touch.
std::string tumblers(const std::string& integrator) {
    std::string bodies;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    const char* shapes[] = {"brick", "ball", "rod"};
    for (int i = 0; i < 101; ++i) {
        if (i) bodies += ",";
        bodies += "{\"name\": \"b" + std::to_string(i) + "\", \"shape\": \"" + shapes[i % 3] +
                  "\", \"mass\": " + std::to_string(1.0f + float(i % 7)) + ", \"position\": [" +
                  std::to_string(20 * (i % 10)) + ", " + std::to_string(10 + 20 * (i / 10)) +
                  ", 0], \"linear_velocity\": [" + std::to_string(u(rng)) + ", " +
                  std::to_string(u(rng)) + ", 0], \"angular_velocity\": [" +
                  std::to_string(u(rng)) + ", " + std::to_string(u(rng)) + ", " +
                  std::to_string(u(rng)) + "]}";
    }
    bodies += ", {\"name\": \"fixed\", \"shape\": \"brick\", \"static\": true, \"position\": [0, -100, 0]}";
    return R"({"format": "rubble-scene", "version": 1, "name": "tumblers",
      "simulation": {"dt": 0.01, "integrator": ")" + integrator + R"(",
                     "collision": {"method": "particles"}, "solver": {"type": "jacobi"}},
      "shapes": {"brick": {"type": "box", "half_extents": [0.1, 0.3, 0.6]},
                 "ball": {"type": "sphere", "radius": 0.2},
                 "rod": {"type": "box", "half_extents": [0.05, 0.05, 1.0]}},
      "bodies": [)" + bodies + "]}";
}

class IntegrateTwin : public test::GpuTest {};

TEST_F(IntegrateTwin, IntegrateVelocitiesMatchesCpu) {
    auto d = deviceStage(tumblers("symplectic"));
    BodyArrays& s = d->in.bodies;
    // Forces and torques on some bodies, on both paths.
    for (std::uint32_t i = 0; i < s.count(); i += 3) {
        s.forces[i].force = shared::vec4(1.0f + float(i), -2.0f, 0.5f);
        s.forces[i].torque = shared::vec4(0.1f, 0.2f * float(i % 5), -0.3f);
    }
    gpu::DeviceBodies& b = d->bodies;
    ASSERT_TRUE(b.uploadForces(d->q(), s.forces).ok());
    const float4 g = toFloat4(d->in.scene.simulation.gravity);
    ASSERT_TRUE(gpu::integrateVelocities(d->q(), b, g, 0.01f).ok());
    std::vector<BodyVelocity> beforeForces(s.count());
    integrateVelocities(s.momenta, s.forces, s.masses, s.poses, s.velocities, beforeForces, g,
                        0.01f);
    std::vector<BodyMomentum> momenta(s.count());
    std::vector<BodyVelocity> velocities(s.count()), atStart(s.count());
    ASSERT_TRUE(gpu::download(d->context(), b.momenta, std::span(momenta)).ok());
    ASSERT_TRUE(gpu::download(d->context(), b.velocities, std::span(velocities)).ok());
    ASSERT_TRUE(gpu::download(d->context(), b.atStart, std::span(atStart)).ok());
    test::expectNearRel(momenta, s.momenta, 1e-5f);
    test::expectNearRel(velocities, s.velocities, 1e-5f);
    test::expectNearRel(atStart, beforeForces, 1e-5f);
}

void checkPositions(test::DeviceStage& d, bool symplectic) {
    BodyArrays& s = d.in.bodies;
    gpu::DeviceBodies& b = d.bodies;
    // Velocities at the start for explicit Euler: the current ones, on both paths.
    const std::vector<BodyVelocity> atStart = s.velocities;
    ASSERT_TRUE(b.copyVelocities(d.q(), b.atStart).ok());
    ASSERT_TRUE(gpu::integratePositions(d.q(), b, 0.01f, symplectic).ok());
    integratePositions(s.poses, s.velocities, atStart, s.momenta, s.masses, 0.01f, symplectic);
    std::vector<BodyPose> poses(s.count());
    std::vector<BodyVelocity> velocities(s.count());
    ASSERT_TRUE(gpu::download(d.context(), b.poses, std::span(poses)).ok());
    ASSERT_TRUE(gpu::download(d.context(), b.velocities, std::span(velocities)).ok());
    test::expectNearRel(poses, s.poses, 1e-5f);
    test::expectNearRel(velocities, s.velocities, 1e-5f);
}

TEST_F(IntegrateTwin, IntegratePositionsSymplecticMatchesCpu) {
    auto d = deviceStage(tumblers("symplectic"));
    checkPositions(*d, true);
}

TEST_F(IntegrateTwin, IntegratePositionsExplicitMatchesCpu) {
    auto d = deviceStage(tumblers("explicit"));
    checkPositions(*d, false);
}

TEST_F(IntegrateTwin, AbsorbVelocityChangeMatchesCpu) {
    auto d = deviceStage(tumblers("symplectic"));
    BodyArrays& s = d->in.bodies;
    gpu::DeviceBodies& b = d->bodies;
    // "before" is the current velocities; "after" a changed copy, uploaded as the velocities.
    std::vector<BodyVelocity> before = s.velocities, after = s.velocities;
    for (std::size_t i = 0; i < after.size(); ++i) {
        after[i].linear = add4(after[i].linear, vec4(0.1f * float(i % 4), -0.5f, 0.2f));
        after[i].angular = add4(after[i].angular, vec4(0.3f, 0.0f, -0.1f * float(i % 3)));
    }
    ASSERT_TRUE(gpu::upload(d->context(), b.before, std::span<const BodyVelocity>(before)).ok());
    ASSERT_TRUE(
        gpu::upload(d->context(), b.velocities, std::span<const BodyVelocity>(after)).ok());
    ASSERT_TRUE(gpu::absorbVelocityChange(d->q(), b).ok());
    absorbVelocityChange(s.momenta, before, after, s.masses, s.poses);
    std::vector<BodyMomentum> momenta(s.count());
    ASSERT_TRUE(gpu::download(d->context(), b.momenta, std::span(momenta)).ok());
    test::expectNearRel(momenta, s.momenta, 1e-5f);
}

// With no contacts, the two backends run the same per-element code: after 200 steps the
// trajectories agree to float round-off (1e-4 relative, from the device's own math library).
TEST_F(IntegrateTwin, AWorldWithoutContactsStepsAlikeOnBothBackends) {
    for (const char* integrator : {"symplectic", "explicit"}) {
        World gpuWorld = deviceWorld(tumblers(integrator));
        std::string cpuScene = tumblers(integrator);
        const std::string particles = "\"collision\": {\"method\": \"particles\"}, ";
        cpuScene.replace(cpuScene.find(particles), particles.size(), "");
        cpuScene.replace(cpuScene.find("jacobi"), 6, "pgs");
        World cpuWorld = test::worldFromText(cpuScene);
        for (int i = 0; i < 200; ++i) {
            ASSERT_TRUE(gpuWorld.step().ok());
            ASSERT_TRUE(cpuWorld.step().ok());
        }
        for (std::uint32_t i = 0; i < cpuWorld.bodyCount(); ++i) {
            const BodyState a = gpuWorld.body(i), b = cpuWorld.body(i);
            for (int k = 0; k < 3; ++k) {
                EXPECT_TRUE(test::nearRel(a.position[k], b.position[k], 1e-4f)) << integrator << i;
                EXPECT_TRUE(test::nearRel(a.linearVelocity[k], b.linearVelocity[k], 1e-4f));
                EXPECT_TRUE(test::nearRel(a.angularVelocity[k], b.angularVelocity[k], 1e-4f));
            }
            EXPECT_NEAR(std::fabs(glm::dot(a.orientation, b.orientation)), 1.0f, 1e-5f);
        }
    }
}

TEST_F(IntegrateTwin, ForcesAndImpulsesFromTheHostReachTheDevice) {
    World w = deviceWorld(tumblers("symplectic"));
    const BodyState start = w.body(0);
    w.addForce(0, glm::vec3(100.0f, 0.0f, 0.0f));
    ASSERT_TRUE(w.step().ok());
    const BodyState afterForce = w.body(0);
    // dv = F dt / m on top of gravity's.
    EXPECT_NEAR(afterForce.linearVelocity.x - start.linearVelocity.x, 100.0f * 0.01f / start.mass,
                1e-4f);
    w.applyImpulse(0, glm::vec3(0.0f, 0.0f, 2.0f), afterForce.position);
    ASSERT_TRUE(w.step().ok());
    // The force held for one step only; the impulse changed v_z by J / m.
    const BodyState later = w.body(0);
    EXPECT_NEAR(later.linearVelocity.x, afterForce.linearVelocity.x, 1e-4f);
    EXPECT_NEAR(later.linearVelocity.z - afterForce.linearVelocity.z, 2.0f / start.mass, 1e-4f);
}

} // namespace
} // namespace rubble
