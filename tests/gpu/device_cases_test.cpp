// tests/gpu/device_cases_test.cpp: the physics cases of tests/support/physics_cases.h on the
// OpenCL backend (particles and Jacobi), with the closed forms the CPU reference meets in
// tests/physics.
#include "gpu_fixture.h"
#include "support/physics_cases.h"

namespace rubble {
namespace {

class DeviceCases : public test::GpuTest {};

// The kernels integrate orientations with the same exponential map (rubble/shared/math.h).
TEST_F(DeviceCases, SymplecticSpinTurnsByOmegaTimesT) {
    World w = deviceWorld(test::spinScene("symplectic", test::kDeviceSimulation));
    test::expectSpinTurnsByOmegaTimesT(w);
}

TEST_F(DeviceCases, ExplicitSpinTurnsByOmegaTimesT) {
    World w = deviceWorld(test::spinScene("explicit", test::kDeviceSimulation));
    test::expectSpinTurnsByOmegaTimesT(w);
}

// The device's rows bounce at e times the approach before the step's gravity (as the CPU's), but
// from where the particles first overlap the floor (3.8 cm deep here: particles find no contact
// ahead of time), with the Baumgarte bias lifting the ball out: the rebound keeps e^2 of the
// drop height within 1 cm (0.1 mm and 6 mm measured), where the approach after gravity rose
// 18 cm above it (e = 1) and 4 cm (e = 0.5).
TEST_F(DeviceCases, ElasticBallReboundsToItsDropHeight) {
    World w = deviceWorld(test::dropScene(1.0f, test::kDeviceSimulation));
    test::expectReboundHeight(w, 1.0f, 0.01f, 0.05f);
}
TEST_F(DeviceCases, HalfElasticBallReboundsToAQuarterOfItsDropHeight) {
    World w = deviceWorld(test::dropScene(0.5f, test::kDeviceSimulation));
    test::expectReboundHeight(w, 0.5f, 0.01f, 0.05f);
}

// One restitution threshold for the CPU rows and the kernels' (rubble/shared/constants.h).
TEST_F(DeviceCases, RestitutionThresholdIsHalfAMetrePerSecond) {
    World above = deviceWorld(test::approachScene(0.75f, test::kDeviceSimulation));
    World below = deviceWorld(test::approachScene(0.35f, test::kDeviceSimulation));
    test::expectRestitutionThreshold(above, below);
}

} // namespace
} // namespace rubble
