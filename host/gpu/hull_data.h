// host/gpu/hull_data.h: a world's shapes flattened into the arrays of rubble/shared/hull.h, once
// per world, for the device's SAT narrow phase (host/gpu/sat.cpp uploads them); the host can run
// the shared narrow phase on them too (HullArrays over these vectors).
#pragma once

#include <span>
#include <vector>

#include "host/geometry/shape.h"
#include "rubble/error.h"
#include "rubble/shared/hull.h"

namespace rubble::gpu {

/// Every shape's record and the concatenated hull arrays (indices in them are each shape's own).
struct HullData {
    std::vector<shared::HullShape> shapes; ///< one per shape, in the world's order
    std::vector<shared::float4> vertices;
    std::vector<std::uint32_t> vertexEdges;
    std::vector<std::uint32_t> neighbourStart; ///< per vertex and one more: into neighbours
    std::vector<std::uint32_t> neighbours;
    std::vector<shared::HullHalfEdge> halfEdges;
    std::vector<shared::float4> faces; ///< normal (xyz), offset (w)
    std::vector<std::uint32_t> faceEdges;
    std::vector<shared::HullEdge> edges;
    std::uint32_t largestFace = 0; ///< most vertices of one face, over every hull
};

/// Flattens the shapes: boxes, convex shapes and meshes as their half-edge hulls, spheres and
/// planes as records. Errors: NotSupported naming the shape when a hull face has more than
/// RUBBLE_HULL_MAX_FACE_VERTICES vertices (the device clips faces in private memory).
Result<HullData> flattenShapes(std::span<const Shape> shapes);

/// The arrays as the shared narrow phase reads them, pointing into `data` (host use).
shared::HullArrays hullArraysOf(const HullData& data);

} // namespace rubble::gpu
