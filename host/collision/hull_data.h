// host/collision/hull_data.h: a world's shapes flattened into the arrays of rubble/shared/hull.h,
// once per world, for the SAT narrow phase of rubble/shared/narrow_phase.h: the CPU stage
// (sat_collision.cpp) reads them in place, the device's (host/gpu/sat.cpp) uploads them.
#pragma once

#include <span>
#include <vector>

#include "host/geometry/shape.h"
#include "rubble/shared/clip.h"
#include "rubble/shared/hull.h"

namespace rubble {

/// True for the shapes that collide through their half-edge hull (box, convex, mesh).
inline bool collidesAsHull(ShapeType t) {
    return t == ShapeType::Box || t == ShapeType::Convex || t == ShapeType::Mesh;
}

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

/// The clipping buffers of the shared narrow phase (shared::ClipBuffers) for faces of up to
/// `largestFace` vertices: a clipped polygon holds at most twice as many plus one.
struct ClipSpace {
    std::vector<shared::ClipVertex> polygon, scratch;
    std::vector<shared::LocalContact> candidates;
    explicit ClipSpace(std::uint32_t largestFace = 0)
        : polygon(2 * std::size_t(largestFace) + 1), scratch(polygon.size()),
          candidates(polygon.size()) {}
    shared::ClipBuffers buffers() {
        return shared::ClipBuffers{polygon.data(), scratch.data(), candidates.data()};
    }
};

/// Flattens the shapes: boxes, convex shapes and meshes as their half-edge hulls, spheres and
/// planes as records. Faces of any size (the device's limit is checked in host/gpu/hull_data.h).
HullData flattenHulls(std::span<const Shape> shapes);

/// The arrays as the shared narrow phase reads them, pointing into `data` (host use).
shared::HullArrays hullArraysOf(const HullData& data);

} // namespace rubble
