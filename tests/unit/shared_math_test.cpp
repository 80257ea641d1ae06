// tests/unit/shared_math_test.cpp: rubble/shared/math.h, the per-element math of the host and
// the kernels: the exponential map of quaternions against glm's angle-axis quaternions.
#include "rubble/shared/math.h"

#include <cmath>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

namespace rubble {
namespace {

using shared::float4;

// The angle of the turn between two rotations, rad.
double turnBetween(float4 q, const glm::dquat& expected) {
    const glm::dquat r = glm::normalize(glm::dquat(q.w, q.x, q.y, q.z)) * glm::conjugate(expected);
    return 2.0 * std::atan2(glm::length(glm::dvec3(r.x, r.y, r.z)), std::abs(r.w));
}

TEST(SharedMath, QuatExpIsTheTurnByTwiceItsLengthFromTinyToManyTurns) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(-2.0, 1.0, 0.5));
    // Half angles across the series' range and past it (halved and squared back up to 7 times).
    for (const double half : {0.0, 1e-7, 1e-3, 0.1, 0.49, 0.51, 1.5, 3.0, 10.0, 60.0}) {
        const glm::dvec3 v = axis * half;
        const float4 q = shared::quatExp(shared::vec4(float(v.x), float(v.y), float(v.z)));
        const double norm = std::sqrt(double(q.x) * q.x + double(q.y) * q.y + double(q.z) * q.z +
                                      double(q.w) * q.w);
        EXPECT_NEAR(norm, 1.0, 1e-6) << "half angle " << half;
        // Float round-off of the angle itself grows with it: 1e-7 of the half angle per
        // squaring, at most.
        EXPECT_LT(turnBetween(q, glm::angleAxis(2.0 * half, axis)), 2e-6 + 4e-7 * half)
            << "half angle " << half;
    }
}

TEST(SharedMath, QuatIntegrateTurnsByOmegaDt) {
    const glm::dquat start = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1.0, 1.0, 0.0)));
    const float4 q0 = shared::make4(float(start.x), float(start.y), float(start.z), float(start.w));
    const glm::dvec3 axis(0.0, 0.6, 0.8);
    for (const double omega : {0.01, 10.0, 100.0, 1000.0}) {
        const double dt = 1.0 / 60.0;
        const glm::dvec3 w = axis * omega;
        const float4 q =
            shared::quatIntegrate(q0, shared::vec4(float(w.x), float(w.y), float(w.z)), float(dt));
        // The world-frame turn first, then the start.
        const glm::dquat expected = glm::angleAxis(omega * double(float(dt)), axis) * start;
        EXPECT_LT(turnBetween(q, expected), 2e-6 + 1e-7 * omega * dt) << omega << " rad/s";
    }
}

} // namespace
} // namespace rubble
