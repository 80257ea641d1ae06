// tests/unit/hull_data_test.cpp: host/gpu/hull_data: shapes flattened for the device, and the
// shared narrow phase (rubble/shared/narrow_phase.h, what kernels/sat.cl runs) compiled on the
// host against the reference collideShapes: the same bits over thousands of random pairs.
#include "host/gpu/hull_data.h"

#include <cstring>

#include <gtest/gtest.h>

#include "host/collision/narrow_phase.h"
#include "rubble/shared/narrow_phase.h"
#include "support/pair_cases.h"
#include "random_hull.h"

namespace rubble {
namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

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
        const std::string path = std::string(RUBBLE_SOURCE_DIR) + "/scenes/meshes/" + file;
        Result<TriangleMesh> mesh = loadObjMesh(path, 1.0f, file);
        ASSERT_TRUE(mesh.ok()) << file;
        ShapeDesc d;
        d.type = ShapeType::Mesh;
        d.where = file;
        d.points = mesh->vertices;
        d.triangles = mesh->triangles;
        Result<Shape> s = buildShape(d);
        ASSERT_TRUE(s.ok()) << file;
        shapes.push_back(std::move(*s));
    }
    Result<gpu::HullData> data = gpu::flattenShapes(shapes);
    ASSERT_TRUE(data.ok()) << data.error().describe();
    std::printf("largest face of the shipped meshes' hulls: %u vertices\n", data->largestFace);
    EXPECT_LE(data->largestFace, RUBBLE_HULL_MAX_FACE_VERTICES);
}

// Compares one pair's result from both, bit for bit.
::testing::AssertionResult sameContacts(const ContactSet& cpu, const shared::ContactManifold& d) {
    if (cpu.count != d.count)
        return ::testing::AssertionFailure() << "count " << cpu.count << " vs " << d.count;
    if (cpu.count == 0) return ::testing::AssertionSuccess();
    for (int c = 0; c < 3; ++c)
        if (!sameBits(cpu.normal[c], (&d.normal.x)[c]))
            return ::testing::AssertionFailure() << "normal[" << c << "] " << cpu.normal[c]
                                                 << " vs " << (&d.normal.x)[c];
    for (std::uint32_t i = 0; i < cpu.count; ++i) {
        const LocalContact& p = cpu.points[i];
        const shared::float4 q = d.points[i];
        if (p.feature != d.features[i])
            return ::testing::AssertionFailure() << "point " << i << " feature " << p.feature
                                                 << " vs " << d.features[i];
        if (!sameBits(p.depth, q.w) || !sameBits(p.position.x, q.x) ||
            !sameBits(p.position.y, q.y) || !sameBits(p.position.z, q.z))
            return ::testing::AssertionFailure() << "point " << i << " depth " << p.depth
                                                 << " vs " << q.w;
    }
    return ::testing::AssertionSuccess();
}

// Three steps per pair so that the caches work: the placed pose, a motion of b small enough for
// the cached feature to be reused, and a larger one that runs the full test with a hint.
TEST(HullData, TheSharedNarrowPhaseGivesTheReferenceBits) {
    test::PairCases cases = test::makePairCases(20240611u, 3000);
    Result<gpu::HullData> data = gpu::flattenShapes(cases.in.shapes);
    ASSERT_TRUE(data.ok()) << data.error().describe();
    const shared::HullArrays arrays = gpu::hullArraysOf(*data);
    const float dt = 1.0f / 60.0f;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> sym(-1.0f, 1.0f);
    int failures = 0, contacts = 0, reused = 0;
    const BodyArrays& bodies = cases.in.bodies;
    for (std::size_t i = 0; i < cases.kinds.size() && failures < 10; ++i) {
        const std::uint32_t a = 2 * std::uint32_t(i), b = a + 1;
        const Shape& sa = cases.in.shapes[bodies.shapeOf[a]];
        const Shape& sb = cases.in.shapes[bodies.shapeOf[b]];
        const glm::vec3 relative =
            toVec3(bodies.velocities[b].linear) - toVec3(bodies.velocities[a].linear);
        const float margin = kContactMargin + glm::length(relative) * dt;
        HullPairCache cache;
        shared::PairCache deviceCache = shared::emptyPairCacheItem();
        shared::BodyPose poseB = bodies.poses[b];
        for (int step = 0; step < 3; ++step) {
            if (step > 0) {
                const float move = step == 1 ? 0.0003f : 0.005f;
                poseB.position.x += move * sym(rng);
                poseB.position.y += move * sym(rng);
                poseB.orientation.x += move * sym(rng);
                poseB.orientation = shared::quatNormalize(poseB.orientation);
            }
            const PairContact cpu = collideShapes(sa, transformOf(bodies.poses[a]), sb,
                                                  transformOf(poseB), cache, margin);
            const shared::ContactManifold d = shared::collideShapesItem(
                arrays, data->shapes[bodies.shapeOf[a]],
                shared::transformOfPose(bodies.poses[a]), data->shapes[bodies.shapeOf[b]],
                shared::transformOfPose(poseB), &deviceCache, margin);
            const ::testing::AssertionResult same = sameContacts(cpu.contacts, d);
            if (!same) {
                ADD_FAILURE() << "case " << i << " (" << test::toString(cases.kinds[i])
                              << "), step " << step << ": " << same.message();
                ++failures;
            }
            EXPECT_EQ(std::uint32_t(cache.feature.feature), deviceCache.feature.feature);
            EXPECT_EQ(cache.feature.indexA, deviceCache.feature.indexA);
            EXPECT_EQ(cache.feature.indexB, deviceCache.feature.indexB);
            EXPECT_EQ(cache.feature.vertex, deviceCache.feature.vertex);
            EXPECT_EQ(cache.reusable, deviceCache.reusable != 0u);
            contacts += int(cpu.contacts.count);
            reused += step == 1 && cache.reusable;
        }
    }
    EXPECT_EQ(failures, 0);
    // The cases reach every path: many contacts, many cached features.
    EXPECT_GT(contacts, 5000);
    EXPECT_GT(reused, 1000);
}

} // namespace
} // namespace rubble
