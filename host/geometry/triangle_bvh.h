// host/geometry/triangle_bvh.h: a bounding volume hierarchy over a triangle mesh's triangles,
// built once per static mesh and queried with boxes in the narrow phase (level_collision.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace rubble {

/// An axis-aligned box in the mesh's frame, m.
struct BvhBox {
    glm::vec3 min{0.0f}, max{0.0f};
};

/// One node: a leaf holds `count` triangles from `first` in the hierarchy's order; an inner
/// node (count 0) has its children at `first` and `second`.
struct BvhNode {
    BvhBox box;
    std::uint32_t first = 0, count = 0, second = 0;
};

/// Triangles per leaf, at most.
inline constexpr std::uint32_t kBvhLeafSize = 4;
/// The deepest a built hierarchy goes: splits at the median keep it near log2(n / leaf).
inline constexpr std::uint32_t kBvhMaxDepth = 64;

/// A hierarchy of boxes over triangles, split at the median of the centroids along the axis
/// where they spread most; nodes in depth-first order.
class TriangleBvh {
  public:
    TriangleBvh() = default;
    /// Builds the hierarchy of the triangles (each indexing `vertices`). O(n log n).
    TriangleBvh(std::span<const glm::vec3> vertices, std::span<const glm::uvec3> triangles);

    /// Appends to `out` the index of every triangle whose box overlaps `box` (touching counts),
    /// in ascending order.
    void query(const BvhBox& box, std::vector<std::uint32_t>& out) const;

    std::span<const BvhNode> nodes() const { return nodes_; }
    /// The triangle indices leaf by leaf: a leaf's triangles are order()[first, first + count).
    std::span<const std::uint32_t> order() const { return order_; }
    /// The box of every triangle, by triangle index.
    std::span<const BvhBox> triangleBoxes() const { return boxes_; }

  private:
    std::vector<BvhNode> nodes_;
    std::vector<std::uint32_t> order_; ///< triangle indices, leaf by leaf
    std::vector<BvhBox> boxes_;        ///< per triangle
};

/// True when the closed boxes overlap.
inline bool boxesOverlap(const BvhBox& a, const BvhBox& b) {
    return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y &&
           b.min.y <= a.max.y && a.min.z <= b.max.z && b.min.z <= a.max.z;
}

} // namespace rubble
