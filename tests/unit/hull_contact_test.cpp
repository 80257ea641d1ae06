// tests/unit/hull_contact_test.cpp: host/collision/hull_contact: manifolds of boxes and hulls.
#include "host/collision/hull_contact.h"

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

Transform pose(glm::vec3 t, glm::quat q = glm::quat(1, 0, 0, 0)) {
    return Transform{glm::mat3_cast(q), t};
}

// True when p lies inside the box (half extents h at pose t) grown by slop.
bool insideBox(glm::vec3 p, glm::vec3 h, const Transform& t, float slop) {
    const glm::vec3 local = t.applyInverse(p);
    return std::fabs(local.x) <= h.x + slop && std::fabs(local.y) <= h.y + slop &&
           std::fabs(local.z) <= h.z + slop;
}

TEST(HullContact, BoxOnBoxFaceToFaceGivesFourPoints) {
    const glm::vec3 h(0.5f);
    const HalfEdgeMesh box = boxMesh(h);
    // B sits on A, 1 cm deep, shifted sideways so the overlap is not the whole face.
    const Transform bInA = pose({0.2f, 0.99f, -0.1f});
    const HullContact c = collideHulls(box, box, bInA);
    ASSERT_FALSE(c.separated);
    ASSERT_EQ(c.contacts.count, 4u);
    EXPECT_NEAR(c.contacts.normal.y, 1.0f, 1e-6f);
    for (std::uint32_t i = 0; i < c.contacts.count; ++i) {
        const LocalContact& p = c.contacts.points[i];
        EXPECT_NEAR(p.depth, 0.01f, 1e-5f);
        EXPECT_NEAR(p.position.y, 0.495f, 1e-5f);
        EXPECT_TRUE(insideBox(p.position, h, Transform{}, 0.01f));
        EXPECT_TRUE(insideBox(p.position, h, bInA, 0.01f));
        for (std::uint32_t j = 0; j < i; ++j) EXPECT_NE(p.feature, c.contacts.points[j].feature);
    }
}

TEST(HullContact, BoxOnItsEdgeGivesTwoPoints) {
    const glm::vec3 h(0.5f);
    const HalfEdgeMesh box = boxMesh(h);
    // B turned 45 degrees about z rests on an edge, 1 cm into A's top face.
    const float edgeHeight = 0.5f * std::sqrt(2.0f);
    const glm::quat q = glm::angleAxis(glm::radians(45.0f), glm::vec3(0, 0, 1));
    const Transform bInA = pose({0.0f, 0.5f + edgeHeight - 0.01f, 0.0f}, q);
    const HullContact c = collideHulls(box, box, bInA);
    ASSERT_FALSE(c.separated);
    ASSERT_EQ(c.contacts.count, 2u);
    EXPECT_NEAR(c.contacts.normal.y, 1.0f, 1e-5f);
    for (std::uint32_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(c.contacts.points[i].depth, 0.01f, 1e-4f);
        EXPECT_NEAR(c.contacts.points[i].position.x, 0.0f, 1e-4f);
        EXPECT_NEAR(std::fabs(c.contacts.points[i].position.z), 0.5f, 1e-4f);
    }
}

TEST(HullContact, SeparatedBoxesGiveNothing) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    const HullContact c = collideHulls(box, box, pose({0.0f, 1.1f, 0.0f}));
    EXPECT_TRUE(c.separated);
    EXPECT_EQ(c.contacts.count, 0u);
    EXPECT_EQ(c.feature.feature, SatFeature::FaceA);
}

TEST(HullContact, GapWithinMarginIsANegativeDepth) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    const HullContact c = collideHulls(box, box, pose({0.0f, 1.002f, 0.0f}));
    ASSERT_FALSE(c.separated);
    ASSERT_EQ(c.contacts.count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i) EXPECT_NEAR(c.contacts.points[i].depth, -0.002f, 1e-5f);
}

TEST(HullContact, NormalPointsFromAToB) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    // B below A this time: the normal must point down.
    const HullContact c = collideHulls(box, box, pose({0.1f, -0.98f, 0.0f}));
    ASSERT_GT(c.contacts.count, 0u);
    EXPECT_NEAR(c.contacts.normal.y, -1.0f, 1e-6f);
}

TEST(HullContact, CrossedEdgesGiveOneEdgePoint) {
    const glm::vec3 h(0.5f);
    const HalfEdgeMesh box = boxMesh(h);
    // A's top edge along z; B stands on its edge along x, both turned 45 degrees: edges cross.
    const glm::quat qa = glm::angleAxis(glm::radians(45.0f), glm::vec3(0, 0, 1));
    const glm::quat qb = glm::angleAxis(glm::radians(45.0f), glm::vec3(1, 0, 0));
    const float e = 0.5f * std::sqrt(2.0f);
    const Transform ta = pose({0, 0, 0}, qa), tb = pose({0, 2 * e - 0.01f, 0}, qb);
    const HullContact c = collideHulls(box, box, relative(ta, tb));
    ASSERT_EQ(c.contacts.count, 1u);
    EXPECT_EQ(c.feature.feature, SatFeature::Edges);
    const glm::vec3 nWorld = ta.rotate(c.contacts.normal);
    EXPECT_NEAR(nWorld.y, 1.0f, 1e-4f);
    EXPECT_NEAR(c.contacts.points[0].depth, 0.01f, 1e-4f);
    const glm::vec3 pWorld = ta.apply(c.contacts.points[0].position);
    EXPECT_NEAR(pWorld.x, 0.0f, 1e-4f);
    EXPECT_NEAR(pWorld.z, 0.0f, 1e-4f);
    EXPECT_NEAR(pWorld.y, e - 0.005f, 1e-4f);
}

TEST(HullContact, FeatureIdsStayUnderSmallMotion) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    HullContact before = collideHulls(box, box, pose({0.2f, 0.99f, -0.1f}));
    ASSERT_EQ(before.contacts.count, 4u);
    const glm::quat q = glm::angleAxis(0.01f, glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)));
    HullContact after =
        collideHulls(box, box, pose({0.203f, 0.988f, -0.098f}, q), kContactMargin, before.feature);
    ASSERT_EQ(after.contacts.count, 4u);
    std::vector<std::uint32_t> a, b;
    for (std::uint32_t i = 0; i < 4; ++i) {
        a.push_back(before.contacts.points[i].feature);
        b.push_back(after.contacts.points[i].feature);
    }
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b);
}

} // namespace
} // namespace rubble
