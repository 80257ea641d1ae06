// tests/unit/triangle_contact_test.cpp: static triangles (host/geometry/level_mesh.cpp, edge
// kinds) and their contacts with spheres, capsules and boxes (host/collision/triangle_contact.cpp,
// level_collision.cpp) against closed forms and brute force.
#include <algorithm>
#include <cmath>
#include <random>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "host/collision/hull_data.h"
#include "host/collision/level_collision.h"
#include "host/collision/triangle_contact.h"
#include "host/core/math.h"
#include "host/geometry/shape.h"
#include "rubble/shared/broad_phase.h"
#include "support/level_cases.h"

namespace rubble {
namespace {

// Runs `collide` (a shared triangle function) on a buffer with room for `room` contacts and
// appends what it wrote to `out` in the host's type.
template <typename Collide>
void collectContacts(std::vector<TriangleContact>& out, std::uint32_t room, Collide collide) {
    std::vector<shared::TriangleContact> items(room);
    shared::ContactBuffer buffer{items.data(), 0u, room};
    collide(&buffer);
    for (std::uint32_t i = 0; i < buffer.count; ++i)
        out.push_back(
            {toVec3(items[i].position), items[i].depth, toVec3(items[i].normal), items[i].feature});
}

// Triangle `index` of a level against a sphere, a capsule or a placed hull, as the narrow phase
// collides them (level_collision.cpp).
void collideTriangleSphere(const LevelTriangle& t, std::uint32_t index, glm::vec3 c, float r,
                           float margin, std::vector<TriangleContact>& out) {
    const shared::MeshTriangle m = meshTriangleOf(t, index);
    collectContacts(out, 2, [&](shared::ContactBuffer* b) {
        shared::collideTriangleSphereItem(m, toFloat4(c), r, margin, b);
    });
}

void collideTriangleCapsule(const LevelTriangle& t, std::uint32_t index, const Segment& s, float r,
                            float margin, std::vector<TriangleContact>& out) {
    const shared::MeshTriangle m = meshTriangleOf(t, index);
    const shared::CapsuleSegment segment{toFloat4(s.p0), toFloat4(s.p1)};
    collectContacts(out, 2, [&](shared::ContactBuffer* b) {
        shared::collideTriangleCapsuleItem(m, segment, r, margin, b);
    });
}

void collideTriangleHull(const LevelTriangle& t, std::uint32_t index, PlacedHull& hull,
                         float margin, std::vector<TriangleContact>& out) {
    const shared::MeshTriangle m = meshTriangleOf(t, index);
    collectContacts(out, std::uint32_t(hull.polygon.size()), [&](shared::ContactBuffer* b) {
        shared::collideTriangleHullItem(m, hull.view, margin, b);
    });
}

// A flat grid of n x n quads of side `cell` at y = 0, centred on the origin, facing +y.
TriangleMesh flatGrid(int n, float cell) {
    return test::quadGrid(n, cell, [](float, float) { return 0.0f; });
}

LevelMesh levelOf(const TriangleMesh& mesh) {
    Result<LevelMesh> level = buildLevelMesh(mesh, "test");
    EXPECT_TRUE(level.ok());
    return std::move(*level);
}

Shape boxShape(glm::vec3 half) {
    ShapeDesc d;
    d.type = ShapeType::Box;
    d.halfExtents = half;
    Result<Shape> s = buildShape(d);
    EXPECT_TRUE(s.ok());
    return std::move(*s);
}

shared::RigidTransform at(glm::vec3 p, glm::quat q = glm::quat(1, 0, 0, 0)) {
    shared::BodyPose pose{};
    pose.position = toFloat4(p);
    pose.orientation = toFloat4(q);
    return shared::transformOfPose(pose);
}

TEST(LevelMesh, EdgeKindsFollowTheNeighbours) {
    // Two flat quads: inner edges flat, the rim a boundary.
    const LevelMesh flat = levelOf(flatGrid(2, 1.0f));
    int boundary = 0, flatEdges = 0;
    for (const LevelTriangle& t : flat.triangles)
        for (EdgeKind k : t.edges) (k == EdgeKind::Boundary ? boundary : flatEdges) += 1;
    EXPECT_EQ(boundary, 8); // the 2 x 2 grid's rim: 8 unit edges
    EXPECT_EQ(flatEdges, 8 * 3 - 8);
    // A ridge (roof) is convex seen from above, a valley concave; flipping one triangle's
    // winding does not change that.
    for (bool flip : {false, true})
        for (float apex : {0.5f, -0.5f}) {
            TriangleMesh m;
            m.vertices = {{0, apex, 0}, {0, apex, 1}, {-1, 0, 0}, {1, 0, 0}};
            m.triangles = {{0, 2, 1}, flip ? glm::uvec3(0, 3, 1) : glm::uvec3(0, 1, 3)};
            const LevelMesh level = levelOf(m);
            const LevelTriangle& left = level.triangles[0];
            ASSERT_GT(left.normal.y, 0.0f);
            EXPECT_EQ(left.edges[2], apex > 0 ? EdgeKind::Convex : EdgeKind::Concave)
                << "apex " << apex << " flip " << flip;
        }
}

TEST(TriangleContact, SphereOnAFaceTouchesAlongItsNormal) {
    const LevelMesh level = levelOf(flatGrid(1, 2.0f));
    std::vector<TriangleContact> out;
    collideTriangleSphere(level.triangles[0], 0, glm::vec3(-0.5f, 0.3f, -0.5f), 0.35f, 0.01f, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].depth, 0.05f, 1e-6f);
    EXPECT_NEAR(out[0].normal.y, 1.0f, 1e-6f);
    EXPECT_NEAR(out[0].position.y, -0.025f, 1e-6f);
    // From below, the other side.
    out.clear();
    collideTriangleSphere(level.triangles[0], 0, glm::vec3(-0.5f, -0.3f, -0.5f), 0.35f, 0.01f, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].normal.y, -1.0f, 1e-6f);
    // Out of reach.
    out.clear();
    collideTriangleSphere(level.triangles[0], 0, glm::vec3(-0.5f, 0.4f, -0.5f), 0.35f, 0.01f, out);
    EXPECT_TRUE(out.empty());
}

TEST(TriangleContact, SphereMatchesBruteForceDistanceNearBoundaryEdges) {
    // One lone triangle: every edge is a boundary, so the normal is the true closest direction.
    TriangleMesh m;
    m.vertices = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
    m.triangles = {{0, 1, 2}};
    const LevelMesh level = levelOf(m);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.5f, 1.5f);
    int touched = 0;
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 c(u(rng), u(rng) * 0.5f, u(rng));
        // The distance by sampling the triangle densely.
        float best = 1e9f;
        for (int a = 0; a <= 200; ++a)
            for (int b = 0; a + b <= 200; ++b) {
                const glm::vec3 p(float(b) / 200.0f, 0.0f, float(a) / 200.0f);
                best = std::min(best, glm::length(c - p));
            }
        std::vector<TriangleContact> out;
        collideTriangleSphere(level.triangles[0], 0, c, 0.3f, 0.0f, out);
        if (best > 0.3f + 0.01f) {
            EXPECT_TRUE(out.empty());
            continue;
        }
        if (best < 0.3f - 0.01f) {
            ASSERT_EQ(out.size(), 1u) << i;
        }
        if (out.empty()) continue;
        ++touched;
        EXPECT_NEAR(out[0].depth, 0.3f - best, 0.008f) << i;
        EXPECT_NEAR(glm::length(out[0].normal), 1.0f, 1e-5f);
    }
    EXPECT_GT(touched, 100);
}

TEST(TriangleContact, SpherePastAFlatInternalEdgeKeepsTheFaceNormal) {
    // A sphere over triangle 1 of a flat quad, collided with triangle 0: its closest feature is
    // the shared (flat) diagonal, and the normal stays straight up.
    const LevelMesh level = levelOf(flatGrid(1, 2.0f));
    std::vector<TriangleContact> out;
    for (const LevelTriangle& t : level.triangles)
        collideTriangleSphere(t, 0, glm::vec3(0.6f, 0.25f, 0.6f), 0.3f, 0.01f, out);
    ASSERT_FALSE(out.empty());
    for (const TriangleContact& c : out) {
        EXPECT_NEAR(c.normal.y, 1.0f, 1e-6f);
        EXPECT_NEAR(c.depth, 0.05f, 1e-6f);
    }
}

TEST(TriangleContact, CapsuleLyingOnAFaceTouchesAtBothEnds) {
    const LevelMesh level = levelOf(flatGrid(1, 4.0f));
    const Segment s{{-1.2f, 0.18f, -1.5f}, {-0.2f, 0.18f, -1.5f}};
    std::vector<TriangleContact> out;
    collideTriangleCapsule(level.triangles[0], 0, s, 0.2f, 0.01f, out);
    ASSERT_EQ(out.size(), 2u);
    for (const TriangleContact& c : out) {
        EXPECT_NEAR(c.depth, 0.02f, 1e-6f);
        EXPECT_NEAR(c.normal.y, 1.0f, 1e-6f);
    }
    EXPECT_NEAR(std::abs(out[0].position.x - out[1].position.x), 1.0f, 1e-5f);
    // Standing on its end: one point, depth from the lower end.
    out.clear();
    collideTriangleCapsule(level.triangles[0], 0, Segment{{-1, 0.15f, -1.5f}, {-1, 1.15f, -1.5f}},
                           0.2f, 0.01f, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].depth, 0.05f, 1e-6f);
}

TEST(TriangleContact, BoxOnAFlatMeshTouchesLikeOnAPlane) {
    // A box a little into a flat mesh of many triangles, turned about y, anywhere on it: every
    // contact points up and is as deep as the box is in, as a plane's would be.
    const LevelMesh level = levelOf(flatGrid(10, 0.5f));
    const Shape box = boxShape(glm::vec3(0.4f, 0.25f, 0.3f));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f), angle(0.0f, 6.28f);
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 p(u(rng), 0.25f - 0.003f, u(rng));
        const glm::quat q = glm::angleAxis(angle(rng), glm::vec3(0, 1, 0));
        const shared::RigidTransform t = at(p, q);
        const shared::BodyBox wb =
            shared::worldBoxItem(flattenHulls(std::span<const Shape>(&box, 1)).shapes[0], t, 0.01f);
        LevelScratch scratch;
        std::vector<shared::ContactManifold> out;
        collideLevel(level, at(glm::vec3(0.0f)), box, t, Aabb{toVec3(wb.min), toVec3(wb.max)},
                     0.01f, scratch, out);
        ASSERT_EQ(out.size(), 1u) << "one normal, one manifold; case " << i;
        EXPECT_EQ(out[0].count, 4u);
        EXPECT_NEAR(out[0].normal.y, 1.0f, 1e-6f);
        for (std::uint32_t k = 0; k < out[0].count; ++k)
            EXPECT_NEAR(out[0].points[k].w, 0.003f, 1e-5f) << i;
    }
}

TEST(TriangleContact, BoxDeepestPointMatchesBruteForceOnATiltedTriangle) {
    // A large triangle, a box tilted and pushed into it from above: the deepest contact is the
    // box's lowest corner below the triangle's plane.
    TriangleMesh m;
    m.vertices = {{-10, 0, -10}, {-10, 0, 10}, {10, 0, -10}};
    m.triangles = {{0, 1, 2}};
    const LevelMesh level = levelOf(m);
    const Shape box = boxShape(glm::vec3(0.5f, 0.3f, 0.2f));
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 200; ++i) {
        const glm::quat q = glm::normalize(glm::quat(1.0f + u(rng), u(rng), u(rng), u(rng)));
        const glm::vec3 p(-3.0f + u(rng), 0.0f, -3.0f + u(rng));
        // Lift so that the lowest corner is 0..2 cm under the plane.
        float lowest = 1e9f;
        for (const glm::vec3& v : box.halfEdge.vertices) lowest = std::min(lowest, (q * v).y);
        const float depth = 0.01f + 0.01f * u(rng);
        const glm::vec3 placed = p + glm::vec3(0.0f, -lowest - depth, 0.0f);
        PlacedHull hull;
        placeHull(box.halfEdge, glm::mat3_cast(q), placed, hull);
        std::vector<TriangleContact> out;
        collideTriangleHull(level.triangles[0], 0, hull, 0.005f, out);
        ASSERT_FALSE(out.empty()) << i;
        float deepest = -1e9f;
        for (const TriangleContact& c : out) {
            deepest = std::max(deepest, c.depth);
            EXPECT_GT(c.normal.y, 0.999f) << "the face is the least penetrating axis, case " << i;
        }
        EXPECT_NEAR(deepest, depth, 1e-4f) << i;
    }
}

TEST(TriangleContact, BoxBesideABoundaryEdgeIsPushedSideways) {
    // A box whose side overlaps a lone triangle's edge by 1 cm and reaches far below it: the
    // edge is a boundary, so the least penetrating axis (sideways) is the normal.
    TriangleMesh m;
    m.vertices = {{0, 0, -5}, {0, 0, 5}, {5, 0, 0}};
    m.triangles = {{0, 1, 2}};
    const LevelMesh level = levelOf(m);
    const Shape box = boxShape(glm::vec3(0.5f));
    PlacedHull hull;
    placeHull(box.halfEdge, glm::mat3(1.0f), glm::vec3(-0.49f, 0.0f, 0.0f), hull);
    std::vector<TriangleContact> out;
    collideTriangleHull(level.triangles[0], 0, hull, 0.005f, out);
    ASSERT_FALSE(out.empty());
    for (const TriangleContact& c : out) {
        EXPECT_NEAR(c.normal.x, -1.0f, 1e-5f);
        EXPECT_NEAR(c.depth, 0.01f, 1e-5f);
    }
    // The same box over a neighbour across a flat edge never takes that axis.
    const LevelMesh two = levelOf(flatGrid(1, 10.0f));
    for (const LevelTriangle& t : two.triangles) {
        out.clear();
        placeHull(box.halfEdge, glm::mat3(1.0f), glm::vec3(0.0f, 0.49f, 0.0f), hull);
        collideTriangleHull(t, 0, hull, 0.005f, out);
        for (const TriangleContact& c : out) EXPECT_NEAR(c.normal.y, 1.0f, 1e-6f);
    }
}

// Whether edgePairsMayWinItem leaves out the edge pairs of `t` and the placed `hull` for `best`
// and `margin` (each corner's excess over the face planes found as collideTriangleHullItem finds
// it); when it does, checks that no axis across an edge of each separates the two by more than
// what an edge pair must beat.
bool edgePairsLeftOut(const shared::MeshTriangle& t, const PlacedHull& hull, float best,
                      float margin) {
    const shared::PlacedHull& h = hull.view;
    float excess[3] = {-1e30f, -1e30f, -1e30f};
    std::uint32_t excessFace[3] = {0u, 0u, 0u};
    for (std::uint32_t f = 0; f < h.hull.faceCount; ++f)
        for (std::uint32_t k = 0; k < 3; ++k) {
            const float over = shared::dot3(hull.faces[f], t.v[k]) - hull.faces[f].w;
            if (over > excess[k]) {
                excess[k] = over;
                excessFace[k] = f;
            }
        }
    if (shared::edgePairsMayWinItem(t, h, best, margin, excess, excessFace)) return false;
    const float threshold = std::min(best + RUBBLE_TRIANGLE_EDGE_BIAS, margin);
    for (std::uint32_t e = 0; e < h.hull.edgeCount; ++e)
        for (std::uint32_t k = 0; k < 3; ++k) {
            const shared::float4 axis =
                shared::cross3(hull.edgeDirections[e], shared::sub4(t.v[(k + 1) % 3], t.v[k]));
            if (shared::length3(axis) < 1e-6f) continue;
            for (float sign : {1.0f, -1.0f}) {
                const shared::float4 n = shared::scale4(shared::normalize3(axis), sign);
                const float separation =
                    shared::placedMinItem(h, n) - shared::triangleMaxItem(t, n);
                EXPECT_LE(separation, threshold) << "hull edge " << e << ", triangle edge " << k;
            }
        }
    return true;
}

TEST(TriangleContact, EdgePairsLeftOutNeverSeparateByMoreThanTheBound) {
    // A box near a tilted triangle with boundary edges, far from the origin as on a large
    // level: whenever the edge pairs are left out, none separates by more than it must to win.
    TriangleMesh m;
    m.vertices = {{80.0f, 0.0f, 80.0f}, {80.6f, 0.15f, 80.1f}, {80.2f, -0.1f, 80.7f}};
    m.triangles = {{0, 1, 2}};
    const LevelMesh level = levelOf(m);
    const shared::MeshTriangle t = meshTriangleOf(level.triangles[0], 0);
    const Shape box = boxShape(glm::vec3(0.5f, 0.3f, 0.4f));
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
    int leftOut = 0;
    for (int i = 0; i < 4000; ++i) {
        const glm::quat q = glm::normalize(glm::quat(1.0f + u(rng), u(rng), u(rng), u(rng)));
        // A point of the triangle, and the box placed so that its centre is within reach of it.
        const float a = unit(rng), b = unit(rng) * (1.0f - a);
        const glm::vec3 onTriangle = level.triangles[0].v[0] +
                                     a * (level.triangles[0].v[1] - level.triangles[0].v[0]) +
                                     b * (level.triangles[0].v[2] - level.triangles[0].v[0]);
        const glm::vec3 centre = onTriangle + 0.7f * glm::vec3(u(rng), u(rng), u(rng));
        PlacedHull hull;
        placeHull(box.halfEdge, glm::mat3_cast(q), centre, hull);
        const float best = -0.03f + 0.04f * unit(rng), margin = 0.004f + 0.01f * unit(rng);
        if (edgePairsLeftOut(t, hull, best, margin)) ++leftOut;
    }
    EXPECT_GT(leftOut, 100) << "the bound leaves the edges out of some cases";

    // A corner 5 mm outside two faces of the box, beside the edge between them, with the
    // triangle's edge across that edge: the pair's axis separates by 7 mm, more than the corner's
    // 5 mm excess over either face, so that corner bounds nothing.
    const float d = 0.005f;
    const glm::vec3 v0(0.5f + d, 0.3f + d, 0.0f);
    TriangleMesh beside;
    beside.vertices = {v0, v0 + glm::vec3(0.5f, -0.5f, 0.0f), v0 + glm::vec3(0.5f, 0.5f, 0.3f)};
    beside.triangles = {{0, 1, 2}};
    const LevelMesh besideLevel = levelOf(beside);
    PlacedHull hull;
    placeHull(box.halfEdge, glm::mat3(1.0f), glm::vec3(0.0f), hull);
    EXPECT_FALSE(edgePairsLeftOut(meshTriangleOf(besideLevel.triangles[0], 0), hull, d, 0.02f));
}

TEST(LevelCollision, ReduceKeepsTheDeepestAndTheCorners) {
    std::vector<TriangleContact> contacts;
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
            contacts.push_back({glm::vec3(float(i), 0.0f, float(j)), 0.001f * float(i + j),
                                glm::vec3(0, 1, 0), std::uint32_t(i * 5 + j)});
    std::vector<std::uint32_t> all, kept;
    for (std::uint32_t k = 0; k < contacts.size(); ++k) all.push_back(k);
    reduceContacts(contacts, all, kept);
    ASSERT_EQ(kept.size(), 4u);
    EXPECT_EQ(kept[0], 24u); // the deepest, (4, 4)
    std::vector<std::uint32_t> corners{0u, 4u, 20u, 24u};
    for (std::uint32_t k : kept)
        EXPECT_NE(std::find(corners.begin(), corners.end(), k), corners.end()) << k;
}

} // namespace
} // namespace rubble
