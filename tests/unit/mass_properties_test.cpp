// tests/unit/mass_properties_test.cpp: host/core/mass_properties against closed forms.
#include <numbers>
#include "host/core/mass_properties.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "host/geometry/convex_hull.h"
#include "host/geometry/shape.h"

namespace rubble {
namespace {

void expectTensorNear(const glm::dmat3& a, const glm::dmat3& b, double tol) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(a[c][r], b[c][r], tol) << "entry " << r << "," << c;
}

TEST(MassProperties, BoxMatchesClosedForm) {
    const MassProperties mp = boxMassProperties({0.5f, 1.0f, 1.5f});
    EXPECT_DOUBLE_EQ(mp.volume, 6.0);
    // I = m/12 (b^2 + c^2) with full side lengths 1, 2, 3 and m = 6.
    expectTensorNear(mp.inertia, glm::dmat3(6.5, 0, 0, 0, 5.0, 0, 0, 0, 2.5), 1e-12);
}

TEST(MassProperties, SphereMatchesClosedForm) {
    const MassProperties mp = sphereMassProperties(2.0f);
    const double volume = 4.0 / 3.0 * std::numbers::pi * 8.0;
    EXPECT_NEAR(mp.volume, volume, 1e-12);
    expectTensorNear(mp.inertia, glm::dmat3(0.4 * volume * 4.0), 1e-9);
}

TEST(MassProperties, UnitTetrahedronMatchesClosedForm) {
    const std::vector<glm::vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    // Counter-clockwise seen from outside.
    const std::vector<glm::uvec3> t{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const MassProperties mp = polyhedronMassProperties(v, t);
    EXPECT_NEAR(mp.volume, 1.0 / 6.0, 1e-15);
    EXPECT_NEAR(mp.centre.x, 0.25, 1e-15);
    EXPECT_NEAR(mp.centre.y, 0.25, 1e-15);
    EXPECT_NEAR(mp.centre.z, 0.25, 1e-15);
    // About the centroid: diagonal 1/80, products of inertia -(-1/480) = +1/480.
    const double d = 1.0 / 80.0, o = 1.0 / 480.0;
    expectTensorNear(mp.inertia, glm::dmat3(d, o, o, o, d, o, o, o, d), 1e-15);
}

TEST(MassProperties, InwardWindingGivesNegativeVolume) {
    const std::vector<glm::vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<glm::uvec3> t{{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    EXPECT_NEAR(polyhedronMassProperties(v, t).volume, -1.0 / 6.0, 1e-15);
}

TEST(MassProperties, HullOfBoxCornersEqualsBox) {
    const glm::vec3 h(0.3f, 0.7f, 1.1f);
    std::vector<glm::vec3> corners;
    for (int i = 0; i < 8; ++i)
        corners.emplace_back(i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z);
    // Shift the box so that the centre of mass is not at the origin.
    for (glm::vec3& c : corners) c += glm::vec3(2.0f, -1.0f, 0.5f);
    Result<ConvexPolygons> hull = computeConvexHull(corners, "test");
    ASSERT_TRUE(hull.ok()) << hull.error().describe();
    EXPECT_EQ(hull->faces.size(), 6u);
    const MassProperties fromHull = polyhedronMassProperties(hull->vertices, hull->triangles());
    const MassProperties box = boxMassProperties(h);
    EXPECT_NEAR(fromHull.volume, box.volume, 1e-6);
    EXPECT_NEAR(fromHull.centre.x, 2.0, 1e-6);
    EXPECT_NEAR(fromHull.centre.y, -1.0, 1e-6);
    EXPECT_NEAR(fromHull.centre.z, 0.5, 1e-6);
    expectTensorNear(fromHull.inertia, box.inertia, 1e-6);
}

TEST(MassProperties, ConvexShapeIsCentredOnItsCentreOfMass) {
    ShapeDesc d;
    d.name = "wedge";
    d.type = ShapeType::Convex;
    d.where = "test: shapes.wedge";
    d.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Result<Shape> s = buildShape(d);
    ASSERT_TRUE(s.ok()) << s.error().describe();
    EXPECT_NEAR(s->centreShift.x, 0.25f, 1e-6f);
    glm::dvec3 sum(0.0);
    for (const glm::vec3& v : s->hull.vertices) sum += glm::dvec3(v);
    // The centroid of a tetrahedron's vertices is its centre of mass.
    EXPECT_NEAR(glm::length(sum / 4.0), 0.0, 1e-6);
}

TEST(MassProperties, ClosedConcaveMeshUsesItsOwnVolume) {
    // An L-shaped prism: two unit cubes side by side and one on top, as a closed mesh built
    // from the hull would overestimate the volume (hull volume 3.5 vs 3).
    ShapeDesc d;
    d.name = "l";
    d.type = ShapeType::Mesh;
    d.where = "test: shapes.l";
    // Profile in the xy plane, extruded along z from 0 to 1.
    const std::vector<glm::vec2> profile{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    for (float z : {0.0f, 1.0f})
        for (glm::vec2 p : profile) d.points.emplace_back(p.x, p.y, z);
    const std::uint32_t n = 6;
    // Bottom (z = 0, normal -z) and top (z = 1, normal +z), fanned from the reflex-free corner 0
    // is wrong for a concave profile, so triangulate by hand.
    const std::vector<glm::uvec3> cap{{0, 3, 1}, {1, 3, 2}, {0, 5, 3}, {3, 5, 4}};
    for (glm::uvec3 t : cap) d.triangles.emplace_back(t.x, t.y, t.z);
    for (glm::uvec3 t : cap) d.triangles.emplace_back(t.x + n, t.z + n, t.y + n);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = (i + 1) % n;
        d.triangles.emplace_back(i, j, j + n);
        d.triangles.emplace_back(i, j + n, i + n);
    }
    Result<Shape> s = buildShape(d);
    ASSERT_TRUE(s.ok()) << s.error().describe();
    EXPECT_TRUE(isClosedMesh(s->mesh));
    EXPECT_NEAR(s->unitMass.volume, 3.0, 1e-6);
    EXPECT_NEAR(s->centreShift.x, 5.0f / 6.0f, 1e-6f);
    EXPECT_NEAR(s->centreShift.y, 5.0f / 6.0f, 1e-6f);
}

TEST(MassProperties, PrincipalAxesDiagonaliseTheTetrahedron) {
    const double d = 1.0 / 80.0, o = 1.0 / 480.0;
    const glm::dmat3 inertia(d, o, o, o, d, o, o, o, d);
    const PrincipalAxes pa = principalAxes(inertia);
    const glm::dmat3 r = glm::mat3_cast(pa.axes);
    const glm::dmat3 rebuilt = r * glm::dmat3(pa.moments.x, 0, 0, 0, pa.moments.y, 0, 0, 0, pa.moments.z) *
                               glm::transpose(r);
    expectTensorNear(rebuilt, inertia, 1e-15);
    // Eigenvalues d + 2o (along (1,1,1)) and d - o twice.
    std::vector<double> m{pa.moments.x, pa.moments.y, pa.moments.z};
    std::sort(m.begin(), m.end());
    EXPECT_NEAR(m[0], d - o, 1e-15);
    EXPECT_NEAR(m[1], d - o, 1e-15);
    EXPECT_NEAR(m[2], d + 2 * o, 1e-15);
    EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
}

TEST(MassProperties, PrincipalAxesOfARotatedBox) {
    const glm::dmat3 diag(2.0, 0, 0, 0, 5.0, 0, 0, 0, 7.0);
    const glm::dmat3 rot = glm::mat3_cast(glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 2, 3))));
    const glm::dmat3 inertia = rot * diag * glm::transpose(rot);
    const PrincipalAxes pa = principalAxes(inertia);
    const glm::dmat3 r = glm::mat3_cast(pa.axes);
    const glm::dmat3 rebuilt =
        r * glm::dmat3(pa.moments.x, 0, 0, 0, pa.moments.y, 0, 0, 0, pa.moments.z) * glm::transpose(r);
    expectTensorNear(rebuilt, inertia, 1e-12);
}

} // namespace
} // namespace rubble
