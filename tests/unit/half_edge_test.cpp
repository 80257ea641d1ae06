// tests/unit/half_edge_test.cpp: host/geometry/half_edge: merging, invariants, hill climbing.
#include "host/geometry/half_edge.h"

#include <array>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "host/geometry/shape.h"
#include "host/geometry/obj_mesh.h"
#include "random_hull.h"

namespace rubble {
namespace {

ConvexPolygons boxTriangles(glm::vec3 h) {
    const ConvexPolygons box = boxPolygons(h);
    ConvexPolygons t;
    t.vertices = box.vertices;
    for (const glm::uvec3& tri : box.triangles()) t.faces.push_back({tri.x, tri.y, tri.z});
    return t;
}

TEST(HalfEdge, BoxHasSixFacesAndTwelveEdges) {
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(boxPolygons({0.5f, 1.0f, 1.5f}), "box");
    ASSERT_TRUE(m.ok()) << m.error().describe();
    EXPECT_EQ(m->vertexCount(), 8u);
    EXPECT_EQ(m->edgeCount(), 12u);
    EXPECT_EQ(m->faceCount(), 6u);
    EXPECT_TRUE(checkHalfEdgeMesh(*m, "box").ok());
}

TEST(HalfEdge, BoxFromTrianglesMergesToSixFaces) {
    const ConvexPolygons tris = boxTriangles({0.5f, 0.25f, 2.0f});
    ASSERT_EQ(tris.faces.size(), 12u);
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(tris, "box");
    ASSERT_TRUE(m.ok()) << m.error().describe();
    EXPECT_EQ(m->faceCount(), 6u);
    EXPECT_EQ(m->edgeCount(), 12u);
    for (const HalfEdgeFace& f : m->faces) {
        // Axis-aligned unit normals, each face a quad.
        EXPECT_NEAR(glm::length(f.normal), 1.0f, 1e-6f);
        EXPECT_NEAR(std::fabs(f.normal.x) + std::fabs(f.normal.y) + std::fabs(f.normal.z), 1.0f,
                    1e-6f);
    }
    for (std::uint32_t f = 0; f < m->faceCount(); ++f) EXPECT_EQ(faceVertices(*m, f).size(), 4u);
}

TEST(HalfEdge, TwinsWalkBackAndLoopsClose) {
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(boxPolygons(glm::vec3(1.0f)), "box");
    ASSERT_TRUE(m.ok());
    for (std::uint32_t h = 0; h < m->edges.size(); ++h) {
        const HalfEdge& e = m->edges[h];
        EXPECT_EQ(e.twin, h ^ 1u);
        EXPECT_EQ(m->edges[e.twin].origin, m->edges[e.next].origin);
        EXPECT_NE(m->edges[e.twin].face, e.face);
    }
}

TEST(HalfEdge, OpenSurfaceIsBadInputNamingTheShape) {
    ConvexPolygons box = boxPolygons(glm::vec3(1.0f));
    box.faces.pop_back();
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(box, "scene.json: shapes.crate");
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.error().kind, ErrorKind::BadInput);
    EXPECT_EQ(m.error().where, "scene.json: shapes.crate");
    EXPECT_NE(m.error().message.find("open"), std::string::npos) << m.error().message;
}

TEST(HalfEdge, InwardWindingIsBadInput) {
    ConvexPolygons box = boxPolygons(glm::vec3(1.0f));
    for (auto& f : box.faces) std::reverse(f.begin(), f.end());
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(box, "inside-out");
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.error().kind, ErrorKind::BadInput);
    EXPECT_NE(m.error().message.find("inward"), std::string::npos) << m.error().message;
}

TEST(HalfEdge, BrokenTwinIsCaughtByTheCheck) {
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(boxPolygons(glm::vec3(1.0f)), "box");
    ASSERT_TRUE(m.ok());
    HalfEdgeMesh broken = *m;
    broken.edges[3].twin = 5;
    const Status st = checkHalfEdgeMesh(broken, "box");
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("twin"), std::string::npos) << st.error().message;
}

TEST(HalfEdge, HillClimbingMatchesBruteForceOnBox) {
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(boxPolygons({0.3f, 0.7f, 1.1f}), "box");
    ASSERT_TRUE(m.ok());
    std::mt19937 rng(7);
    std::normal_distribution<float> g;
    for (int i = 0; i < 1000; ++i) {
        const glm::vec3 d(g(rng), g(rng), g(rng));
        const std::uint32_t hill = supportVertex(*m, d, std::uint32_t(i % 8));
        const std::uint32_t brute = supportVertexBruteForce(*m, d);
        EXPECT_FLOAT_EQ(glm::dot(d, m->vertices[hill]), glm::dot(d, m->vertices[brute]));
    }
}

TEST(HalfEdge, ShapesCarryTheirHalfEdgeMesh) {
    ShapeDesc d;
    d.type = ShapeType::Box;
    d.halfExtents = {0.5f, 0.5f, 0.5f};
    Result<Shape> s = buildShape(d);
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->halfEdge.faceCount(), 6u);

    // A convex shape whose points hold a cube: Qhull's facets merge back into 6 faces.
    ShapeDesc c;
    c.type = ShapeType::Convex;
    for (int i = 0; i < 8; ++i)
        c.points.emplace_back(i & 1 ? 1.0f : 0.0f, i & 2 ? 1.0f : 0.0f, i & 4 ? 1.0f : 0.0f);
    c.points.emplace_back(0.5f, 0.5f, 1.0f); // on a face: not a hull vertex
    Result<Shape> cube = buildShape(c);
    ASSERT_TRUE(cube.ok()) << cube.error().describe();
    EXPECT_EQ(cube->halfEdge.faceCount(), 6u);
    EXPECT_EQ(cube->halfEdge.edgeCount(), 12u);
    EXPECT_EQ(cube->halfEdge.vertexCount(), 8u);
}

TEST(HalfEdge, HillClimbingMatchesBruteForceOnRandomHulls) {
    // 100 random hulls, 1,000 random directions each, from a random start vertex.
    std::mt19937 rng(2015);
    int failures = 0;
    for (int h = 0; h < 100; ++h) {
        const Shape shape = test::randomHull(rng);
        const HalfEdgeMesh& m = shape.halfEdge;
        std::uniform_int_distribution<std::uint32_t> start(0, m.vertexCount() - 1);
        for (int i = 0; i < 1000; ++i) {
            const glm::vec3 d = test::randomDirection(rng);
            const float hill = glm::dot(d, m.vertices[supportVertex(m, d, start(rng))]);
            const float brute = glm::dot(d, m.vertices[supportVertexBruteForce(m, d)]);
            // Merged faces are planar within kMergeDistance; nothing else may differ.
            if (!(hill >= brute - kMergeDistance * shape.boundingRadius) && ++failures <= 5)
                ADD_FAILURE() << "hull " << h << " direction " << i << ": hill " << hill
                              << ", brute " << brute;
        }
    }
    EXPECT_EQ(failures, 0);
}

TEST(HalfEdge, RandomHullsKeepTheInvariants) {
    std::mt19937 rng(11);
    for (int i = 0; i < 200; ++i) {
        const Shape shape = test::randomHull(rng);
        const HalfEdgeMesh& m = shape.halfEdge;
        EXPECT_TRUE(checkHalfEdgeMesh(m, "random").ok());
        EXPECT_EQ(long(m.vertexCount()) - long(m.edgeCount()) + long(m.faceCount()), 2);
        // Each undirected edge's record matches its half-edges.
        for (std::uint32_t k = 0; k < m.edgeCount(); ++k) {
            const HalfEdgeEdge& e = m.edgeRecords[k];
            EXPECT_EQ(e.origin, m.vertices[m.edges[2 * k].origin]);
            EXPECT_EQ(e.direction, m.vertices[m.edges[2 * k + 1].origin] - e.origin);
        }
    }
}

ConvexPolygons objTriangles(const std::string& file) {
    const std::string path = std::string(RUBBLE_SOURCE_DIR) + "/scenes/meshes/" + file;
    Result<TriangleMesh> mesh = loadObjMesh(path, 1.0f, file);
    EXPECT_TRUE(mesh.ok());
    ConvexPolygons p;
    p.vertices = mesh->vertices;
    for (const glm::uvec3& t : mesh->triangles) p.faces.push_back({t.x, t.y, t.z});
    return p;
}

TEST(HalfEdge, ObjMeshesGiveValidHulls) {
    for (const char* file : {"rock.obj", "l_block.obj", "bowl.obj"}) {
        Result<Shape> s = test::shippedMeshShape(file, 1.0f);
        ASSERT_TRUE(s.ok()) << file << ": " << s.error().describe();
        EXPECT_TRUE(checkHalfEdgeMesh(s->halfEdge, file).ok()) << file;
        EXPECT_TRUE(isClosedMesh(s->mesh)) << file;
    }
    // The L's hull is a prism over a pentagon: the inner corner is cut off.
    Result<Shape> block = test::shippedMeshShape("l_block.obj", 1.0f);
    ASSERT_TRUE(block.ok());
    EXPECT_EQ(block->halfEdge.faceCount(), 7u);
    EXPECT_EQ(block->halfEdge.edgeCount(), 15u);
    EXPECT_EQ(block->halfEdge.vertexCount(), 10u);
}

TEST(HalfEdge, ConvexObjTrianglesBuildDirectly) {
    Result<HalfEdgeMesh> rock = buildHalfEdgeMesh(objTriangles("rock.obj"), "rock.obj");
    ASSERT_TRUE(rock.ok()) << rock.error().describe();
    EXPECT_EQ(rock->faceCount(), 20u);
    EXPECT_EQ(rock->vertexCount(), 12u);
    EXPECT_EQ(rock->edgeCount(), 30u);
}

TEST(HalfEdge, ConcaveObjTrianglesAreBadInput) {
    for (const char* file : {"l_block.obj", "bowl.obj"}) {
        Result<HalfEdgeMesh> m = buildHalfEdgeMesh(objTriangles(file), file);
        ASSERT_FALSE(m.ok()) << file;
        EXPECT_EQ(m.error().kind, ErrorKind::BadInput);
        EXPECT_EQ(m.error().where, file);
        EXPECT_NE(m.error().message.find("convex"), std::string::npos) << m.error().message;
    }
}

// A UV sphere of radius 1 as triangles wound outward: rings x segments vertices and poles.
ConvexPolygons uvSphere(std::uint32_t rings, std::uint32_t segments) {
    ConvexPolygons p;
    p.vertices.push_back({0.0f, 1.0f, 0.0f});
    for (std::uint32_t i = 1; i < rings; ++i) {
        const double theta = 3.14159265358979 * double(i) / double(rings);
        for (std::uint32_t j = 0; j < segments; ++j) {
            const double phi = 2.0 * 3.14159265358979 * double(j) / double(segments);
            p.vertices.push_back(glm::vec3(glm::dvec3(std::sin(theta) * std::cos(phi),
                                                      std::cos(theta),
                                                      std::sin(theta) * std::sin(phi))));
        }
    }
    p.vertices.push_back({0.0f, -1.0f, 0.0f});
    const auto south = std::uint32_t(p.vertices.size() - 1);
    auto at = [&](std::uint32_t ring, std::uint32_t j) { return 1 + ring * segments + j % segments; };
    for (std::uint32_t j = 0; j < segments; ++j) p.faces.push_back({0, at(0, j + 1), at(0, j)});
    for (std::uint32_t i = 0; i + 2 < rings; ++i)
        for (std::uint32_t j = 0; j < segments; ++j) {
            p.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            p.faces.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    for (std::uint32_t j = 0; j < segments; ++j)
        p.faces.push_back({south, at(rings - 2, j), at(rings - 2, j + 1)});
    return p;
}

// A mesh beyond kWholeMeshCheckLimit is built and checked edge by edge and by hill climbing:
// each face plane is still the support plane every vertex agrees with.
TEST(HalfEdge, LargeMeshPlanesAreSupportPlanes) {
    const ConvexPolygons sphere = uvSphere(60, 120);
    ASSERT_GT(double(sphere.vertices.size()) * double(sphere.faces.size()), kWholeMeshCheckLimit);
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(sphere, "sphere");
    ASSERT_TRUE(m.ok()) << m.error().describe();
    float worst = 0.0f;
    for (const HalfEdgeFace& f : m->faces) {
        float best = -1e30f;
        for (const glm::vec3& v : m->vertices) best = std::max(best, glm::dot(f.normal, v));
        worst = std::max(worst, std::fabs(best - f.offset));
    }
    // Merged faces are planar within kMergeDistance of the radius (1): hill climbing over them
    // may stop that close to the true support.
    EXPECT_LT(worst, kMergeDistance);
}

// The edge-by-edge check still refuses a large mesh that is not convex: one vertex pushed out
// (a spike) or in (a dent).
TEST(HalfEdge, LargeNonConvexMeshIsRefused) {
    for (const float push : {1.05f, 0.95f}) {
        ConvexPolygons sphere = uvSphere(60, 120);
        sphere.vertices[1000] *= push;
        Result<HalfEdgeMesh> m = buildHalfEdgeMesh(sphere, "sphere");
        ASSERT_FALSE(m.ok()) << "push " << push;
        EXPECT_NE(m.error().message.find("the mesh is not convex"), std::string::npos)
            << m.error().message;
    }
}

// Large coplanar regions merge in near-linear time with the same result as the exact test: a
// box whose faces are each a grid of triangles becomes six quads.
TEST(HalfEdge, LargeCoplanarGroupsMergeToOneFace) {
    const std::uint32_t n = 40; // cells a side: 2 n^2 triangles a face, > kExactMergeVertices
    ConvexPolygons box;
    std::map<std::array<int, 3>, std::uint32_t> index;
    auto vertex = [&](std::array<int, 3> c) {
        const auto [it, added] = index.try_emplace(c, std::uint32_t(box.vertices.size()));
        if (added) box.vertices.push_back(glm::vec3(c[0], c[1], c[2]) / float(n) - 0.5f);
        return it->second;
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            for (std::uint32_t i = 0; i < n; ++i)
                for (std::uint32_t j = 0; j < n; ++j) {
                    auto corner = [&](std::uint32_t a, std::uint32_t b) {
                        std::array<int, 3> c{};
                        c[axis] = side ? int(n) : 0;
                        c[(axis + 1) % 3] = int(a);
                        c[(axis + 2) % 3] = int(b);
                        return vertex(c);
                    };
                    const std::uint32_t q[4] = {corner(i, j), corner(i + 1, j),
                                                corner(i + 1, j + 1), corner(i, j + 1)};
                    // Outward: counter-clockwise seen from the side the face looks at.
                    if (side) {
                        box.faces.push_back({q[0], q[1], q[2]});
                        box.faces.push_back({q[0], q[2], q[3]});
                    } else {
                        box.faces.push_back({q[0], q[2], q[1]});
                        box.faces.push_back({q[0], q[3], q[2]});
                    }
                }
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(box, "grid box");
    ASSERT_TRUE(m.ok()) << m.error().describe();
    EXPECT_EQ(m->faceCount(), 6u);
    EXPECT_EQ(m->vertexCount(), 8u);
}

} // namespace
} // namespace rubble
