// tests/unit/half_edge_test.cpp: host/geometry/half_edge: merging, invariants, hill climbing.
#include "host/geometry/half_edge.h"

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

// The OBJ meshes shipped in scenes/meshes.
Result<Shape> meshShape(const std::string& file) {
    const std::string path = std::string(RUBBLE_SOURCE_DIR) + "/scenes/meshes/" + file;
    Result<TriangleMesh> mesh = loadObjMesh(path, 1.0f, file);
    if (!mesh) return mesh.error();
    ShapeDesc d;
    d.type = ShapeType::Mesh;
    d.where = file;
    d.points = mesh->vertices;
    d.triangles = mesh->triangles;
    return buildShape(d);
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
        Result<Shape> s = meshShape(file);
        ASSERT_TRUE(s.ok()) << file << ": " << s.error().describe();
        EXPECT_TRUE(checkHalfEdgeMesh(s->halfEdge, file).ok()) << file;
        EXPECT_TRUE(isClosedMesh(s->mesh)) << file;
    }
    // The L's hull is a prism over a pentagon: the inner corner is cut off.
    Result<Shape> block = meshShape("l_block.obj");
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

} // namespace
} // namespace rubble
