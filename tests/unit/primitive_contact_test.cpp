// tests/unit/primitive_contact_test.cpp: host/collision/primitive_contact: spheres and planes.
#include "host/collision/primitive_contact.h"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include "host/geometry/shape.h"

namespace rubble {
namespace {

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

} // namespace
} // namespace rubble
