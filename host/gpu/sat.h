// host/gpu/sat.h: the SAT method's narrow phase on the device (kernels/sat.cl, collideShapes):
// the shapes' hulls flattened once per world (host/gpu/hull_data.h), and one manifold per pair
// with last step's features. The CPU twin is SatCollision::narrowPhase.
#pragma once

#include <cstdint>
#include <span>

#include "host/geometry/shape.h"
#include "host/gpu/pairs.h"

namespace rubble::gpu {

/// The hulls of a world's shapes and each body's shape.
struct DeviceShapes {
    Buffer shapes, shapeOf, vertices, vertexEdges, neighbourStart, neighbours, halfEdges, faces,
        faceEdges, edges;
    /// The static level meshes (flattenLevels): each shape's level or RUBBLE_NO_LEVEL, the
    /// levels, their hierarchies' nodes and their triangles.
    Buffer levelOf, levels, levelNodes, levelTriangles;
    /// Errors: NotSupported for a hull the device cannot clip (flattenShapes), Device.
    Status create(StageQueue& q, std::span<const Shape> shapes,
                  std::span<const std::uint32_t> shapeOf);
};

/// Stage narrowPhase: one manifold per pair of `pairs.current` into `pairs.manifolds`, with
/// last step's features (`pairs.previous`); `spin` and `boxes` are the broad phase's. A pair of
/// a body and a static level mesh gets the group of its triangles' contacts with the deepest
/// point (rubble/shared/level_contact.h). The contact count and
/// the largest depth go to the status block.
Status collideShapes(StageQueue& q, const DeviceBodies& b, const DeviceShapes& shapes,
                     const Buffer& spin, const Buffer& boxes, PairStore& pairs, float dt);

} // namespace rubble::gpu
