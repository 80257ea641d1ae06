// host/gpu/hull_data.cpp: the device's limit on hull faces, over the flattening of
// host/collision/hull_data.cpp.
#include "host/gpu/hull_data.h"

#include <string>

#include "host/collision/triangle_contact.h"
#include "host/core/math.h"

namespace rubble::gpu {

LevelData flattenLevels(std::span<const Shape> shapes) {
    LevelData d;
    d.levelOf.assign(shapes.size(), RUBBLE_NO_LEVEL);
    for (std::size_t index = 0; index < shapes.size(); ++index) {
        if (!shapes[index].level) continue;
        const LevelMesh& level = *shapes[index].level;
        d.levelOf[index] = std::uint32_t(d.levels.size());
        const std::span<const BvhNode> nodes = level.bvh.nodes();
        const std::span<const std::uint32_t> order = level.bvh.order();
        d.levels.push_back(
            shared::LevelShape{std::uint32_t(d.nodes.size()), std::uint32_t(nodes.size()),
                               std::uint32_t(d.triangles.size()), std::uint32_t(order.size())});
        for (const BvhNode& n : nodes)
            d.nodes.push_back(shared::LevelNode{toFloat4(n.box.min), toFloat4(n.box.max), n.first,
                                                n.count, n.second, 0u});
        // Leaf order: a leaf's triangles are consecutive; each keeps its own index.
        for (const std::uint32_t k : order)
            d.triangles.push_back(meshTriangleOf(level.triangles[k], k));
    }
    return d;
}

Result<HullData> flattenShapes(std::span<const Shape> shapes) {
    for (std::size_t index = 0; index < shapes.size(); ++index) {
        const Shape& s = shapes[index];
        if (!collidesAsHull(s.type)) continue;
        for (std::uint32_t f = 0; f < s.halfEdge.faceCount(); ++f) {
            const auto n = std::uint32_t(faceVertices(s.halfEdge, f).size());
            if (n > RUBBLE_HULL_MAX_FACE_VERTICES)
                return makeError(ErrorKind::NotSupported,
                                 "shapes[" + std::to_string(index) + "]" +
                                     (s.name.empty() ? "" : " (" + s.name + ")"),
                                 "a face of its hull has " + std::to_string(n) +
                                     " vertices; the device's SAT narrow phase clips faces "
                                     "of at most " +
                                     std::to_string(RUBBLE_HULL_MAX_FACE_VERTICES) +
                                     " (collide it with particles, or simplify the hull)");
        }
    }
    return flattenHulls(shapes);
}

} // namespace rubble::gpu
