// host/geometry/triangle_bvh.cpp: building and querying the triangle hierarchy.
#include "host/geometry/triangle_bvh.h"

#include <algorithm>
#include <array>

#include "host/core/assert.h"

namespace rubble {
namespace {

BvhBox merged(const BvhBox& a, const BvhBox& b) {
    return BvhBox{glm::min(a.min, b.min), glm::max(a.max, b.max)};
}

// One node to build: triangles order[first, first + count), and where its record goes.
struct BuildTask {
    std::uint32_t node, first, count;
};

} // namespace

TriangleBvh::TriangleBvh(std::span<const glm::vec3> vertices,
                         std::span<const glm::uvec3> triangles) {
    const auto n = std::uint32_t(triangles.size());
    boxes_.resize(n);
    std::vector<glm::vec3> centroids(n);
    for (std::uint32_t t = 0; t < n; ++t) {
        const glm::vec3 a = vertices[triangles[t].x], b = vertices[triangles[t].y],
                        c = vertices[triangles[t].z];
        boxes_[t] = BvhBox{glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
        centroids[t] = (a + b + c) / 3.0f;
    }
    order_.resize(n);
    for (std::uint32_t t = 0; t < n; ++t) order_[t] = t;
    if (n == 0) return;
    nodes_.reserve(2 * (n / kBvhLeafSize + 1));
    // Depth first: the second child waits on the stack while the first is built.
    std::vector<BuildTask> stack{{0, 0, n}};
    nodes_.emplace_back();
    while (!stack.empty()) {
        const BuildTask task = stack.back();
        stack.pop_back();
        BvhBox box = boxes_[order_[task.first]];
        BvhBox spread{centroids[order_[task.first]], centroids[order_[task.first]]};
        for (std::uint32_t k = task.first + 1; k < task.first + task.count; ++k) {
            box = merged(box, boxes_[order_[k]]);
            spread.min = glm::min(spread.min, centroids[order_[k]]);
            spread.max = glm::max(spread.max, centroids[order_[k]]);
        }
        nodes_[task.node].box = box;
        if (task.count <= kBvhLeafSize) {
            nodes_[task.node].first = task.first;
            nodes_[task.node].count = task.count;
            continue;
        }
        const glm::vec3 extent = spread.max - spread.min;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        // Ties broken by index so that the hierarchy does not depend on the sort's whims.
        const std::uint32_t half = task.count / 2;
        const auto begin = order_.begin() + task.first;
        std::nth_element(begin, begin + half, begin + task.count,
                         [&](std::uint32_t x, std::uint32_t y) {
                             const float cx = centroids[x][axis], cy = centroids[y][axis];
                             return cx < cy || (cx == cy && x < y);
                         });
        const auto first = std::uint32_t(nodes_.size());
        nodes_.emplace_back();
        const auto second = std::uint32_t(nodes_.size());
        nodes_.emplace_back();
        nodes_[task.node].second = second;
        nodes_[task.node].first = first; // inner nodes keep their first child here
        stack.push_back({second, task.first + half, task.count - half});
        stack.push_back({first, task.first, half});
    }
}

void TriangleBvh::query(const BvhBox& box, std::vector<std::uint32_t>& out) const {
    if (nodes_.empty()) return;
    const std::size_t start = out.size();
    std::array<std::uint32_t, 2 * kBvhMaxDepth> stack{};
    std::uint32_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const BvhNode& node = nodes_[stack[--top]];
        if (!boxesOverlap(node.box, box)) continue;
        if (node.count > 0) {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k)
                if (boxesOverlap(boxes_[order_[k]], box)) out.push_back(order_[k]);
            continue;
        }
        RUBBLE_ASSERT(top + 2 <= stack.size());
        stack[top++] = node.second;
        stack[top++] = node.first;
    }
    std::sort(out.begin() + std::ptrdiff_t(start), out.end());
}

} // namespace rubble
