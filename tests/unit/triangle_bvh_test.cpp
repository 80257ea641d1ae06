// tests/unit/triangle_bvh_test.cpp: the triangle hierarchy (host/geometry/triangle_bvh.cpp)
// against a brute-force test of every triangle's box.
#include <random>

#include <gtest/gtest.h>

#include "host/geometry/triangle_bvh.h"

namespace rubble {
namespace {

TEST(TriangleBvh, QueriesMatchBruteForceOnRandomTriangles) {
    std::mt19937 rng(41);
    std::uniform_real_distribution<float> where(-50.0f, 50.0f), size(0.01f, 3.0f), unit(-1, 1);
    for (const std::uint32_t n : {1u, 3u, 5u, 100u, 20000u}) {
        std::vector<glm::vec3> vertices;
        std::vector<glm::uvec3> triangles;
        for (std::uint32_t t = 0; t < n; ++t) {
            const glm::vec3 c(where(rng), where(rng) * 0.2f, where(rng));
            const float s = size(rng);
            const auto base = std::uint32_t(vertices.size());
            for (int k = 0; k < 3; ++k)
                vertices.push_back(c + s * glm::vec3(unit(rng), unit(rng), unit(rng)));
            triangles.emplace_back(base, base + 1, base + 2);
        }
        const TriangleBvh bvh(vertices, triangles);
        ASSERT_EQ(bvh.triangleBoxes().size(), n);
        std::size_t hits = 0;
        for (int q = 0; q < 300; ++q) {
            const glm::vec3 c(where(rng), where(rng) * 0.2f, where(rng));
            const glm::vec3 h = glm::vec3(size(rng), size(rng), size(rng)) * (q % 3 == 0 ? 10.f : 1.f);
            const BvhBox box{c - h, c + h};
            std::vector<std::uint32_t> found;
            bvh.query(box, found);
            std::vector<std::uint32_t> expected;
            for (std::uint32_t t = 0; t < n; ++t)
                if (boxesOverlap(bvh.triangleBoxes()[t], box)) expected.push_back(t);
            ASSERT_EQ(found, expected) << n << " triangles, query " << q;
            hits += found.size();
        }
        if (n >= 100) {
            EXPECT_GT(hits, 0u) << "the queries should meet some triangles";
        }
    }
}

TEST(TriangleBvh, EveryTriangleSitsInOneLeafInsideItsAncestors) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f);
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> triangles;
    for (std::uint32_t t = 0; t < 1000; ++t) {
        for (int k = 0; k < 3; ++k) vertices.emplace_back(u(rng), u(rng), u(rng));
        triangles.emplace_back(3 * t, 3 * t + 1, 3 * t + 2);
    }
    const TriangleBvh bvh(vertices, triangles);
    std::size_t inLeaves = 0;
    for (const BvhNode& node : bvh.nodes()) {
        if (node.count > 0) {
            EXPECT_LE(node.count, kBvhLeafSize);
            inLeaves += node.count;
            continue;
        }
        for (const std::uint32_t child : {node.first, node.second}) {
            const BvhBox& c = bvh.nodes()[child].box;
            EXPECT_TRUE(glm::all(glm::lessThanEqual(node.box.min, c.min)) &&
                        glm::all(glm::greaterThanEqual(node.box.max, c.max)));
        }
    }
    EXPECT_EQ(inLeaves, triangles.size());
}

} // namespace
} // namespace rubble
