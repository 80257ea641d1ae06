// tests/unit/hull_data_test.cpp: host/collision/hull_data and host/gpu/hull_data: shapes
// flattened for the narrow phase, and the device's limit on hull faces.
#include "host/gpu/hull_data.h"

#include <random>

#include <gtest/gtest.h>

#include "host/core/math.h"
#include "random_hull.h"

namespace rubble {
namespace {

TEST(HullData, ABoxIsOneRecordAndItsArrays) {
    ShapeDesc d;
    d.type = ShapeType::Box;
    d.halfExtents = glm::vec3(0.5f, 0.25f, 1.0f);
    d.where = "box";
    Result<Shape> box = buildShape(d);
    ASSERT_TRUE(box.ok());
    ShapeDesc s;
    s.type = ShapeType::Sphere;
    s.radius = 0.3f;
    s.where = "sphere";
    Result<Shape> sphere = buildShape(s);
    ASSERT_TRUE(sphere.ok());
    const std::vector<Shape> shapes = {*sphere, *box, *box};
    Result<gpu::HullData> data = gpu::flattenShapes(shapes);
    ASSERT_TRUE(data.ok()) << data.error().describe();
    ASSERT_EQ(data->shapes.size(), 3u);
    EXPECT_EQ(data->shapes[0].kind, RUBBLE_SHAPE_SPHERE);
    EXPECT_EQ(data->shapes[0].radius, 0.3f);
    const shared::HullShape& b = data->shapes[2];
    EXPECT_EQ(b.kind, RUBBLE_SHAPE_HULL);
    EXPECT_EQ(b.vertexCount, 8u);
    EXPECT_EQ(b.edgeCount, 12u);
    EXPECT_EQ(b.faceCount, 6u);
    EXPECT_EQ(b.vertexStart, 8u);
    EXPECT_EQ(b.halfEdgeStart, 24u);
    EXPECT_EQ(b.edgeStart, 12u);
    EXPECT_EQ(b.faceStart, 6u);
    EXPECT_EQ(data->vertices.size(), 16u);
    EXPECT_EQ(data->halfEdges.size(), 48u);
    EXPECT_EQ(data->neighbourStart.size(), 17u);
    EXPECT_EQ(data->neighbours.size(), 48u);
    EXPECT_EQ(data->largestFace, 4u);
    EXPECT_EQ(b.boundsMax.y, 0.25f);
    // The second box's rings point into its own part of the neighbours.
    EXPECT_EQ(data->neighbourStart[8], 24u);
    // Hill climbing on the flattened hull finds the corner furthest along a direction.
    const shared::Hull h = shared::hullOfItem(gpu::hullArraysOf(*data), b);
    const std::uint32_t v = shared::supportVertexItem(h, shared::vec4(1.0f, -1.0f, 1.0f), 0u);
    EXPECT_EQ(supportVertexBruteForce(box->halfEdge, glm::vec3(1.0f, -1.0f, 1.0f)), v);
}

TEST(HullData, AFaceWithTooManyVerticesIsNotSupported) {
    Result<Shape> disc = test::discShape();
    ASSERT_TRUE(disc.ok());
    const std::vector<Shape> shapes = {*disc};
    Result<gpu::HullData> data = gpu::flattenShapes(shapes);
    ASSERT_FALSE(data.ok());
    EXPECT_EQ(data.error().kind, ErrorKind::NotSupported);
    EXPECT_EQ(data.error().where, "shapes[0]");
    EXPECT_NE(data.error().message.find("100 vertices"), std::string::npos)
        << data.error().message;
}

// The OBJ meshes of scenes/meshes collide as their hulls on the device too.
TEST(HullData, TheShippedMeshesFit) {
    std::vector<Shape> shapes;
    for (const char* file : {"rock.obj", "l_block.obj", "bowl.obj"}) {
        Result<Shape> s = test::shippedMeshShape(file, 1.0f);
        ASSERT_TRUE(s.ok()) << file;
        shapes.push_back(std::move(*s));
    }
    Result<gpu::HullData> data = gpu::flattenShapes(shapes);
    ASSERT_TRUE(data.ok()) << data.error().describe();
    std::printf("largest face of the shipped meshes' hulls: %u vertices\n", data->largestFace);
    EXPECT_LE(data->largestFace, RUBBLE_HULL_MAX_FACE_VERTICES);
}

// Hill climbing on the flattened hulls (what the narrow phase runs) finds the vertex furthest
// along a direction, from any start, on random hulls.
TEST(HullData, HillClimbingFindsTheSupportVertex) {
    std::mt19937 rng(11);
    std::vector<Shape> shapes;
    for (int i = 0; i < 50; ++i) shapes.push_back(test::randomHull(rng));
    const HullData data = flattenHulls(shapes);
    const shared::HullArrays arrays = hullArraysOf(data);
    int failures = 0;
    for (std::size_t h = 0; h < shapes.size(); ++h) {
        const HalfEdgeMesh& m = shapes[h].halfEdge;
        const shared::Hull hull = shared::hullOfItem(arrays, data.shapes[h]);
        std::uniform_int_distribution<std::uint32_t> start(0, m.vertexCount() - 1);
        for (int k = 0; k < 2000; ++k) {
            const glm::vec3 d = test::randomDirection(rng);
            const std::uint32_t v = shared::supportVertexItem(hull, toFloat4(d), start(rng));
            const std::uint32_t best = supportVertexBruteForce(m, d);
            // Ties (equal projections) may pick either vertex.
            if (glm::dot(d, m.vertices[v]) < glm::dot(d, m.vertices[best]) && ++failures <= 5)
                ADD_FAILURE() << "hull " << h << ", direction " << k << ": vertex " << v
                              << " instead of " << best;
        }
    }
    EXPECT_EQ(failures, 0);
}

} // namespace
} // namespace rubble
