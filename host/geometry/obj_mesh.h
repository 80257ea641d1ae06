// host/geometry/obj_mesh.h: OBJ meshes read with tinyobjloader, as vertices and triangles.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rubble/error.h"

namespace rubble {

/// A triangle mesh; triangles index vertices and wind as the file does.
struct TriangleMesh {
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> triangles;
};

/// Reads an OBJ file (polygons are triangulated), scaling every vertex by `scale`. Errors are
/// BadInput at `where` (the scene field that named the file): missing or unreadable file, no
/// faces, non-finite coordinates.
Result<TriangleMesh> loadObjMesh(const std::string& path, float scale, const std::string& where);

} // namespace rubble
