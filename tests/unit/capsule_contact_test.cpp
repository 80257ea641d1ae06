// tests/unit/capsule_contact_test.cpp: capsule mass properties against a numerical integral, and
// capsule contacts (host/collision/capsule_contact.cpp) against brute-force distances.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "host/collision/capsule_contact.h"
#include "host/core/mass_properties.h"
#include "host/core/math.h"
#include "host/geometry/shape.h"

namespace rubble {
namespace {

// The capsule cut into thin discs across y, each disc's inertia summed (midpoint rule).
MassProperties integratedCapsule(double r, double h) {
    MassProperties mp;
    const int slices = 400000;
    const double top = h + r, dy = 2.0 * top / slices;
    double along = 0.0, across = 0.0;
    for (int i = 0; i < slices; ++i) {
        const double y = -top + (i + 0.5) * dy;
        const double beyond = std::max(0.0, std::abs(y) - h);
        const double rho2 = r * r - beyond * beyond;
        if (rho2 <= 0.0) continue;
        const double dm = std::numbers::pi * rho2 * dy;
        mp.volume += dm;
        along += 0.5 * dm * rho2;
        across += dm * (rho2 / 4.0 + y * y);
    }
    mp.inertia = glm::dmat3(0.0);
    mp.inertia[0][0] = mp.inertia[2][2] = across;
    mp.inertia[1][1] = along;
    return mp;
}

TEST(CapsuleMass, MatchesTheIntegralOfItsDiscs) {
    for (const auto& [r, h] : {std::pair{0.3, 0.5}, std::pair{0.05, 1.0}, std::pair{1.0, 0.1},
                              std::pair{0.2, 0.0}}) {
        const MassProperties exact = capsuleMassProperties(float(r), float(h));
        const MassProperties sum = integratedCapsule(r, h);
        EXPECT_NEAR(exact.volume, sum.volume, 1e-6 * sum.volume) << r << " " << h;
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(exact.inertia[k][k], sum.inertia[k][k], 1e-6 * sum.inertia[k][k])
                << r << " " << h << " axis " << k;
        EXPECT_EQ(exact.inertia[0][1], 0.0);
    }
    // With no cylinder it is a sphere.
    const MassProperties ball = capsuleMassProperties(0.2f, 0.0f);
    const MassProperties sphere = sphereMassProperties(0.2f);
    EXPECT_NEAR(ball.volume, sphere.volume, 1e-12);
    EXPECT_NEAR(ball.inertia[0][0], sphere.inertia[0][0], 1e-9);
}

glm::vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> n;
    glm::vec3 v(n(rng), n(rng), n(rng));
    return glm::normalize(v);
}

// The distance between two segments by sampling both densely.
float sampledSegmentDistance(const Segment& a, const Segment& b, int samples) {
    float best = 1e30f;
    for (int i = 0; i <= samples; ++i) {
        const glm::vec3 p = glm::mix(a.p0, a.p1, float(i) / samples);
        for (int j = 0; j <= samples; ++j)
            best = std::min(best, glm::length(p - glm::mix(b.p0, b.p1, float(j) / samples)));
    }
    return best;
}

float deepest(const shared::ContactManifold& m) {
    float d = -1e30f;
    for (std::uint32_t i = 0; i < m.count; ++i) d = std::max(d, m.points[i].w);
    return d;
}

TEST(CapsuleContact, CapsulePairsMatchBruteForce) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const float margin = 0.05f;
    int touching = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const glm::vec3 ca(u(rng), u(rng), u(rng)), cb(u(rng), u(rng), u(rng));
        const glm::vec3 ha = randomUnit(rng) * (0.2f + 0.4f * std::abs(u(rng)));
        const glm::vec3 hb = randomUnit(rng) * (0.2f + 0.4f * std::abs(u(rng)));
        const Segment a{ca - ha, ca + ha}, b{cb - hb, cb + hb};
        const float ra = 0.1f + 0.2f * std::abs(u(rng)), rb = 0.1f + 0.2f * std::abs(u(rng));
        const float sampled = sampledSegmentDistance(a, b, 400);
        const float exact = glm::length(closestSegmentPoints(a, b).onA - closestSegmentPoints(a, b).onB);
        // Sampling overestimates by at most half a step of the longer segment.
        EXPECT_LE(exact, sampled + 1e-5f);
        EXPECT_GE(exact, sampled - 0.6f / 400.0f);
        const shared::ContactManifold m = collideCapsules(a, ra, b, rb, margin);
        const float separation = exact - ra - rb;
        if (separation > margin + 1e-4f) {
            EXPECT_EQ(m.count, 0u) << trial;
            continue;
        }
        if (separation < margin - 1e-4f) {
            ASSERT_GT(m.count, 0u) << trial;
        }
        if (m.count == 0) continue;
        ++touching;
        EXPECT_NEAR(deepest(m), -separation, 2e-4f) << trial;
        const glm::vec3 n = toVec3(m.normal);
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
        // The normal points from a to b: moving b along it separates them.
        if (exact > 1e-3f) {
            const SegmentClosest c = closestSegmentPoints(a, b);
            EXPECT_GT(glm::dot(n, c.onB - c.onA), 0.0f) << trial;
        }
    }
    EXPECT_GT(touching, 30);
}

TEST(CapsuleContact, ParallelCapsulesTouchAtBothEndsOfTheOverlap) {
    // b lies on a, half overlapping it along x.
    const Segment a{{-1, 0, 0}, {1, 0, 0}}, b{{0, 0.39f, 0}, {2, 0.39f, 0}};
    const shared::ContactManifold m = collideCapsules(a, 0.2f, b, 0.2f, 0.01f);
    ASSERT_EQ(m.count, 2u);
    EXPECT_NEAR(m.normal.y, 1.0f, 1e-6f);
    const float xs[2] = {m.points[0].x, m.points[1].x};
    EXPECT_NEAR(std::min(xs[0], xs[1]), 0.0f, 1e-5f);
    EXPECT_NEAR(std::max(xs[0], xs[1]), 1.0f, 1e-5f);
    for (std::uint32_t i = 0; i < 2; ++i) EXPECT_NEAR(m.points[i].w, 0.01f, 1e-5f);
}

// The distance from a point to a box centred on the origin (0 inside).
float boxDistance(glm::vec3 p, glm::vec3 half) {
    return glm::length(p - glm::clamp(p, -half, half));
}

TEST(CapsuleContact, CapsuleBoxMatchesBruteForce) {
    ShapeDesc d;
    d.type = ShapeType::Box;
    d.halfExtents = glm::vec3(0.5f, 0.3f, 0.8f);
    Result<Shape> box = buildShape(d);
    ASSERT_TRUE(box.ok());
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    const float margin = 0.05f;
    int touching = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const glm::vec3 c(u(rng), u(rng), u(rng));
        const glm::vec3 h = randomUnit(rng) * (0.1f + 0.3f * std::abs(u(rng)));
        const Segment s{c - h, c + h};
        const float r = 0.1f + 0.1f * std::abs(u(rng));
        float sampled = 1e30f;
        for (int i = 0; i <= 4000; ++i)
            sampled = std::min(sampled, boxDistance(glm::mix(s.p0, s.p1, i / 4000.0f),
                                                    d.halfExtents));
        const shared::ContactManifold m = collideHullCapsule(box->halfEdge, s, r, margin);
        if (sampled == 0.0f) {
            // The core crosses the box: contacts that push the capsule out.
            EXPECT_GT(m.count, 0u) << trial;
            continue;
        }
        const float separation = sampled - r;
        if (separation > margin + 1e-3f) {
            EXPECT_EQ(m.count, 0u) << trial;
            continue;
        }
        if (separation < margin - 1e-3f) {
            ASSERT_GT(m.count, 0u) << trial;
        }
        if (m.count == 0) continue;
        ++touching;
        EXPECT_NEAR(deepest(m), -separation, 1e-3f) << trial;
        // The normal leaves the box towards the capsule.
        const glm::vec3 n = toVec3(m.normal);
        EXPECT_GT(glm::dot(n, c), 0.0f) << trial;
    }
    EXPECT_GT(touching, 30);
}

TEST(CapsuleContact, CapsuleLyingOnABoxRestsOnTwoPoints) {
    ShapeDesc d;
    d.type = ShapeType::Box;
    d.halfExtents = glm::vec3(1.0f, 0.5f, 1.0f);
    Result<Shape> box = buildShape(d);
    ASSERT_TRUE(box.ok());
    // Radius 0.1, its surface 2 mm into the top face, turned 30 degrees about y.
    const glm::vec3 along = 0.4f * glm::vec3(std::cos(0.5f), 0.0f, std::sin(0.5f));
    const glm::vec3 c(0.2f, 0.598f, -0.1f);
    const shared::ContactManifold m =
        collideHullCapsule(box->halfEdge, Segment{c - along, c + along}, 0.1f, 0.004f);
    ASSERT_EQ(m.count, 2u);
    EXPECT_NEAR(m.normal.y, 1.0f, 1e-6f);
    for (std::uint32_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(m.points[i].w, 0.002f, 1e-5f);
        EXPECT_NEAR(m.points[i].y, 0.5f - 0.001f, 1e-5f);
    }
    const glm::vec3 p0 = toVec3(m.points[0]), p1 = toVec3(m.points[1]);
    EXPECT_NEAR(glm::length(glm::vec2(p1.x - p0.x, p1.z - p0.z)), 0.8f, 1e-5f);
    // Hanging over the edge at x = 1: clipped there.
    const glm::vec3 over(0.9f, 0.598f, 0.0f);
    const glm::vec3 x(0.4f, 0.0f, 0.0f);
    const shared::ContactManifold clipped =
        collideHullCapsule(box->halfEdge, Segment{over - x, over + x}, 0.1f, 0.004f);
    ASSERT_EQ(clipped.count, 2u);
    EXPECT_NEAR(std::max(clipped.points[0].x, clipped.points[1].x), 1.0f, 1e-5f);
    EXPECT_NEAR(std::min(clipped.points[0].x, clipped.points[1].x), 0.5f, 1e-5f);
}

TEST(CapsuleContact, PlaneAndSphere) {
    // Tilted: one end 1 cm in, the other 3 cm clear.
    const Segment s{{-0.5f, 0.19f, 0}, {0.5f, 0.23f, 0}};
    const shared::ContactManifold plane = collidePlaneCapsule({0, 1, 0}, 0.0f, s, 0.2f, 0.02f);
    ASSERT_EQ(plane.count, 1u);
    EXPECT_NEAR(plane.points[0].w, 0.01f, 1e-6f);
    EXPECT_EQ(collidePlaneCapsule({0, 1, 0}, 0.0f, s, 0.2f, 0.04f).count, 2u);
    const shared::ContactManifold ball =
        collideCapsuleSphere(s, 0.2f, glm::vec3(0.1f, 0.6f, 0.0f), 0.2f, 0.0f);
    ASSERT_EQ(ball.count, 1u);
    const glm::vec3 centre(0.1f, 0.6f, 0.0f);
    float sampled = 1e30f;
    for (int i = 0; i <= 10000; ++i)
        sampled = std::min(sampled, glm::length(glm::mix(s.p0, s.p1, i / 10000.0f) - centre));
    EXPECT_GT(ball.normal.y, 0.99f);
    EXPECT_NEAR(ball.points[0].w, 0.4f - sampled, 1e-4f);
}

} // namespace
} // namespace rubble
