// tests/unit/soft_step_test.cpp: mirrors host/dynamics/soft_step.cpp: the soft constraint's
// coefficients against an implicit spring-damper (and the device's, to the bit), the settings'
// caps, and particle contacts refused on the device by name.
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "host/dynamics/soft_step.h"
#include "rubble/shared/soft_step.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// One soft update of a unit mass on C = x without warm start, v' = v - massScale (v + biasRate
// x), is implicit Euler of the spring-damper of that stiffness and damping ratio:
// v' = (v - h omega^2 x) / (1 + 2 h zeta omega + h^2 omega^2) (Catto, "Solver2D: soft step").
TEST(SoftStep, SoftnessIsImplicitEulerOfTheSpringDamper) {
    for (const float hertz : {5.0f, 30.0f, 60.0f, 240.0f})
        for (const float zeta : {0.0f, 0.7f, 2.0f, 10.0f})
            for (const float h : {1.0f / 60.0f, 1.0f / 240.0f, 1.0f / 1000.0f}) {
                const Softness s = makeSoftness(hertz, zeta, h);
                const double omega = 2.0 * std::numbers::pi * hertz;
                const double x = 0.01, v = -0.3;
                const double implicit = (v - h * omega * omega * x) /
                                        (1.0 + 2.0 * h * zeta * omega + h * h * omega * omega);
                const double soft = v - double(s.massScale) * (v + double(s.biasRate) * x);
                EXPECT_NEAR(soft, implicit, 1e-5 * (1.0 + std::abs(implicit)))
                    << hertz << " Hz, zeta " << zeta << ", h " << h;
                EXPECT_NEAR(s.massScale + s.impulseScale, 1.0f, 1e-6f);
            }
    const Softness rigid = makeSoftness(0.0f, 1.0f, 0.01f);
    EXPECT_EQ(rigid.biasRate, 0.0f);
    EXPECT_EQ(rigid.massScale, 1.0f);
    EXPECT_EQ(rigid.impulseScale, 0.0f);
}

// The contact hertz is capped at a quarter of the substep rate.
TEST(SoftStep, SettingsCapTheContactHertz) {
    SolverOptions o;
    o.substeps = 2;
    o.contactHertz = 1000.0f;
    const SoftStepSettings s = makeSoftStepSettings(o, 1.0f / 60.0f);
    EXPECT_FLOAT_EQ(s.h, 1.0f / 120.0f);
    EXPECT_FLOAT_EQ(s.contactHertz, 30.0f);
    o.contactHertz = 10.0f;
    EXPECT_FLOAT_EQ(makeSoftStepSettings(o, 1.0f / 60.0f).contactHertz, 10.0f);
}

// A constraint's spring: the hertz between moving bodies whatever their masses, `againstStill`
// times it against a body that does not move, whichever side it is on.
TEST(SoftStep, SpringsAreStifferAgainstBodiesThatDoNotMove) {
    const float h = 1.0f / 240.0f;
    auto same = [](Softness x, Softness y) {
        EXPECT_FLOAT_EQ(x.biasRate, y.biasRate);
        EXPECT_FLOAT_EQ(x.massScale, y.massScale);
        EXPECT_FLOAT_EQ(x.impulseScale, y.impulseScale);
    };
    same(softnessFor(30.0f, 10.0f, h, 1.0f, 1.0f, 2.0f), makeSoftness(30.0f, 10.0f, h));
    same(softnessFor(30.0f, 10.0f, h, 1.0f, 0.001f, 2.0f), makeSoftness(30.0f, 10.0f, h));
    same(softnessFor(30.0f, 10.0f, h, 1.0f, 0.0f, 2.0f), makeSoftness(60.0f, 10.0f, h));
    same(softnessFor(30.0f, 10.0f, h, 0.0f, 1.0f, 2.0f), makeSoftness(60.0f, 10.0f, h));
    same(softnessFor(60.0f, 2.0f, h, 0.0f, 1.0f, 1.0f), makeSoftness(60.0f, 2.0f, h));
}

// The device's soft step goes through the SAT path's pairs and rows: with particle contacts on
// opencl it is refused naming the option, and says which collision takes it.
TEST(SoftStep, TheDeviceRefusesParticleContactsNamingTheOption) {
    const Error e = test::sceneError(R"({"format": "rubble-scene", "version": 1,
      "simulation": {"backend": "opencl", "collision": {"method": "particles"},
                     "solver": {"type": "soft-step"}},
      "shapes": {"ground": {"type": "plane"}, "box": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "b", "shape": "box", "mass": 1, "position": [0, 0.5, 0]}]})");
    EXPECT_EQ(e.kind, ErrorKind::NotSupported);
    EXPECT_EQ(e.where, "inline.json: simulation.solver.type");
    EXPECT_NE(e.message.find("soft-step"), std::string::npos) << e.message;
    EXPECT_NE(e.message.find("--collision sat"), std::string::npos) << e.message;
}

// The device's springs (shared::softnessItem, kernels/soft_step.cl) are the CPU's to the bit.
TEST(SoftStep, TheDevicesSpringsAreTheCpus) {
    for (const float hertz : {0.0f, 15.0f, 30.0f, 60.0f, 120.0f})
        for (const float zeta : {0.0f, 2.0f, 10.0f})
            for (const float h : {1.0f / 240.0f, 1.0f / 300.0f, 0.01f}) {
                const Softness cpu = makeSoftness(hertz, zeta, h);
                const shared::float4 device = shared::softnessItem(hertz, zeta, h);
                EXPECT_EQ(std::bit_cast<std::uint32_t>(cpu.biasRate),
                          std::bit_cast<std::uint32_t>(device.x))
                    << hertz << " Hz, zeta " << zeta << ", h " << h;
                EXPECT_EQ(std::bit_cast<std::uint32_t>(cpu.massScale),
                          std::bit_cast<std::uint32_t>(device.y));
                EXPECT_EQ(std::bit_cast<std::uint32_t>(cpu.impulseScale),
                          std::bit_cast<std::uint32_t>(device.z));
            }
}

} // namespace
} // namespace rubble
