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

// One restitution threshold for the CPU rows and the kernels' (rubble/shared/constants.h).
TEST_F(DeviceCases, RestitutionThresholdIsHalfAMetrePerSecond) {
    World above = deviceWorld(test::approachScene(0.75f, test::kDeviceSimulation));
    World below = deviceWorld(test::approachScene(0.35f, test::kDeviceSimulation));
    test::expectRestitutionThreshold(above, below);
}

} // namespace
} // namespace rubble
