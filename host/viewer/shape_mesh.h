// host/viewer/shape_mesh.h: triangles to draw each shape with, in the body frame (centre of mass
// at the origin, as the pipelines see the shape).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "rubble/shape.h"

namespace rubble::viewer {

/// One vertex: position (m) and unit normal, body frame.
struct MeshVertex {
    glm::vec3 position;
    glm::vec3 normal;
};

/// An indexed triangle list, counter-clockwise seen from outside.
struct RenderMesh {
    std::vector<MeshVertex> vertices;
    std::vector<std::uint32_t> indices;
};

/// The triangles of a shape: hull faces flat-shaded (box, convex), the mesh's own triangles
/// flat-shaded (mesh), a smooth latitude-longitude sphere (sphere). Planes give no triangles:
/// the renderer draws them as the ground.
RenderMesh buildRenderMesh(const ShapeGeometry& shape);

} // namespace rubble::viewer
