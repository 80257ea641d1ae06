// tests/unit/primitive_contact_test.cpp: spheres and planes (rubble/shared/primitive_contact.h,
// run by the CPU stage and the device).
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "flat_hull.h"
#include "host/geometry/shape.h"
#include "random_hull.h"

namespace rubble {
namespace {

using test::collideHullSphere;
using test::collidePlaneHull;
using test::collidePlaneSphere;
using test::collideSpheres;
using test::ContactSet;
using test::FlatHull;
using test::kContactMargin;
using test::LocalContact;

HalfEdgeMesh boxMesh(glm::vec3 h) {
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(boxPolygons(h), "box");
    EXPECT_TRUE(m.ok());
    return std::move(*m);
}

TEST(PrimitiveContact, SpheresTouchingAlongTheLineOfCentres) {
    const ContactSet c = collideSpheres({0, 0, 0}, 0.5f, {0.9f, 0, 0}, 0.5f);
    ASSERT_EQ(c.count, 1u);
    EXPECT_NEAR(c.normal.x, 1.0f, 1e-6f);
    EXPECT_NEAR(c.points[0].depth, 0.1f, 1e-6f);
    EXPECT_NEAR(c.points[0].position.x, 0.45f, 1e-6f);
    EXPECT_EQ(collideSpheres({0, 0, 0}, 0.5f, {1.1f, 0, 0}, 0.5f).count, 0u);
}

TEST(PrimitiveContact, SphereOnPlane) {
    const ContactSet c = collidePlaneSphere({0, 1, 0}, 0.0f, {1, 0.45f, 2}, 0.5f);
    ASSERT_EQ(c.count, 1u);
    EXPECT_NEAR(c.normal.y, 1.0f, 1e-6f);
    EXPECT_NEAR(c.points[0].depth, 0.05f, 1e-6f);
    EXPECT_NEAR(c.points[0].position.y, -0.025f, 1e-6f);
    EXPECT_EQ(collidePlaneSphere({0, 1, 0}, 0.0f, {0, 0.51f, 0}, 0.5f).count, 0u);
}

TEST(PrimitiveContact, BoxOnPlaneGivesFourPoints) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    // The plane y = -0.49 in the box's frame: the box sinks 1 cm.
    const ContactSet c = collidePlaneHull({0, 1, 0}, -0.49f, box);
    ASSERT_EQ(c.count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(c.points[i].depth, 0.01f, 1e-6f);
        EXPECT_NEAR(c.points[i].position.y, -0.495f, 1e-6f);
    }
}

TEST(PrimitiveContact, TiltedBoxOnPlaneGivesItsLowestCorner) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 1));
    const float corner = -glm::dot(n, glm::vec3(0.5f));
    const ContactSet c = collidePlaneHull(n, corner + 0.01f, box);
    ASSERT_EQ(c.count, 1u);
    EXPECT_NEAR(c.points[0].depth, 0.01f, 1e-5f);
}

TEST(PrimitiveContact, ManyVerticesOnAPlaneKeepFour) {
    // A 100-sided disc lying on the plane: 100 candidates, four kept, spread over the disc.
    Result<Shape> disc = test::discShape();
    ASSERT_TRUE(disc.ok()) << disc.error().describe();
    const ContactSet c = collidePlaneHull({0, 1, 0}, -0.098f, disc->halfEdge);
    ASSERT_EQ(c.count, 4u);
    float span = 0.0f; // the largest distance between two of the points
    for (std::uint32_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(c.points[i].depth, 0.002f, 1e-5f);
        for (std::uint32_t j = 0; j < i; ++j)
            span = std::max(span, glm::length(c.points[i].position - c.points[j].position));
    }
    EXPECT_GT(span, 1.5f); // nearly a diameter (1.6 m)
}

TEST(PrimitiveContact, SphereAgainstBoxFaceEdgeAndInside) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    // Above the top face.
    ContactSet c = collideHullSphere(box, {0.1f, 0.7f, 0.0f}, 0.25f);
    ASSERT_EQ(c.count, 1u);
    EXPECT_NEAR(c.normal.y, 1.0f, 1e-6f);
    EXPECT_NEAR(c.points[0].depth, 0.05f, 1e-6f);
    // Beyond the edge x = y = 0.5: the normal points diagonally.
    c = collideHullSphere(box, {0.6f, 0.6f, 0.0f}, 0.2f);
    ASSERT_EQ(c.count, 1u);
    EXPECT_NEAR(c.normal.x, std::sqrt(0.5f), 1e-5f);
    EXPECT_NEAR(c.normal.y, std::sqrt(0.5f), 1e-5f);
    EXPECT_NEAR(c.points[0].depth, 0.2f - std::sqrt(0.02f), 1e-5f);
    // The centre inside, nearest the +x face.
    c = collideHullSphere(box, {0.4f, 0.0f, 0.1f}, 0.1f);
    ASSERT_EQ(c.count, 1u);
    EXPECT_NEAR(c.normal.x, 1.0f, 1e-6f);
    EXPECT_NEAR(c.points[0].depth, 0.2f, 1e-6f);
    // Clear of the corner.
    EXPECT_EQ(collideHullSphere(box, {0.7f, 0.7f, 0.7f}, 0.3f).count, 0u);
}

// The distance from c to the surface of a convex hull by brute force over every face polygon:
// its projection when inside the polygon, else the nearest point of its edges.
float distanceToSurface(const HalfEdgeMesh& m, glm::vec3 c) {
    float best = 1e30f;
    for (std::uint32_t f = 0; f < m.faceCount(); ++f) {
        const HalfEdgeFace& face = m.faces[f];
        const std::vector<std::uint32_t> loop = faceVertices(m, f);
        const glm::vec3 p = c - face.normal * (glm::dot(face.normal, c) - face.offset);
        bool inside = true;
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const glm::vec3 a = m.vertices[loop[i]], b = m.vertices[loop[(i + 1) % loop.size()]];
            if (glm::dot(glm::cross(b - a, face.normal), p - a) > 0.0f) inside = false;
            const float t = std::clamp(glm::dot(c - a, b - a) / glm::dot(b - a, b - a), 0.0f, 1.0f);
            best = std::min(best, glm::length(c - (a + (b - a) * t)));
        }
        if (inside) best = std::min(best, glm::length(c - p));
    }
    return best;
}

float outside(const HalfEdgeMesh& m, glm::vec3 p) {
    float d = -1e30f;
    for (const HalfEdgeFace& f : m.faces) d = std::max(d, glm::dot(f.normal, p) - f.offset);
    return d;
}

TEST(PrimitiveContact, RandomSpheresAgainstRandomHulls) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> radius(0.05f, 0.6f), offset(-0.3f, 0.1f);
    int failures = 0, outsideCount = 0, insideCount = 0;
    auto fail = [&](int i, const std::string& what) {
        if (++failures <= 5) ADD_FAILURE() << "case " << i << ": " << what;
    };
    for (int h = 0; h < 50; ++h) {
        const Shape shape = test::randomHull(rng);
        const HalfEdgeMesh& m = shape.halfEdge;
        const FlatHull flat(m);
        for (int k = 0; k < 100; ++k) {
            const int i = h * 100 + k;
            // A centre near the surface: a random surface direction, moved in or out.
            const glm::vec3 dir = test::randomDirection(rng);
            const glm::vec3 surface = m.vertices[supportVertex(m, dir)];
            const float r = radius(rng);
            const glm::vec3 c = surface + dir * (r + offset(rng));
            const float inDepth = -outside(m, c); // > 0 when the centre is inside
            const float dist = inDepth > 0.0f ? -inDepth : distanceToSurface(m, c);
            const ContactSet set = collideHullSphere(flat, c, r);
            if (dist - r > kContactMargin + 1e-5f) {
                if (set.count != 0) fail(i, "contact while apart");
                continue;
            }
            if (dist - r < kContactMargin - 1e-5f && set.count != 1) {
                fail(i, "no contact while touching");
                continue;
            }
            if (set.count == 0) continue;
            (inDepth > 0.0f ? insideCount : outsideCount)++;
            const LocalContact& p = set.points[0];
            if (std::fabs(p.depth - (r - dist)) > 1e-5f)
                fail(i,
                     "depth " + std::to_string(p.depth) + ", expected " + std::to_string(r - dist));
            if (std::fabs(glm::length(set.normal) - 1.0f) > 1e-5f) fail(i, "normal is not unit");
            // From the hull to the sphere: moving the sphere along it reduces the overlap.
            if (distanceToSurface(m, c + set.normal * 0.01f) < dist + 0.009f && inDepth <= 0.0f)
                fail(i, "normal does not point away from the hull");
            const float slop = 0.5f * std::fabs(p.depth) + 1e-4f;
            if (outside(m, p.position) > slop || glm::length(p.position - c) - r > slop)
                fail(i, "point outside a shape");
        }
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GT(outsideCount, 1000);
    EXPECT_GT(insideCount, 100);
}

TEST(PrimitiveContact, RandomSphereAndPlanePairs) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), radius(0.1f, 1.0f);
    for (int i = 0; i < 1000; ++i) {
        const glm::vec3 n = test::randomDirection(rng);
        const float d = u(rng), r = radius(rng);
        const glm::vec3 c(u(rng), u(rng), u(rng));
        const float gap = glm::dot(n, c) - d - r;
        const ContactSet set = collidePlaneSphere(n, d, c, r);
        ASSERT_EQ(set.count, gap <= kContactMargin ? 1u : 0u) << i;
        if (set.count == 0) continue;
        EXPECT_NEAR(set.points[0].depth, -gap, 1e-5f);
        // Midway between the plane and the sphere's lowest point.
        EXPECT_NEAR(glm::dot(n, set.points[0].position) - d, 0.5f * gap, 1e-5f);
        // Two spheres: depth is the overlap of the radii.
        const glm::vec3 c2 = c + test::randomDirection(rng) * (2.0f * r * (0.5f + 0.5f * u(rng)));
        const ContactSet pair = collideSpheres(c, r, c2, r);
        const float overlap = 2.0f * r - glm::length(c2 - c);
        ASSERT_EQ(pair.count, -overlap <= kContactMargin ? 1u : 0u);
        if (pair.count) {
            EXPECT_NEAR(pair.points[0].depth, overlap, 1e-5f);
        }
    }
}

} // namespace
} // namespace rubble
