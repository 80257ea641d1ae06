// host/geometry/obj_mesh.h: OBJ meshes read with tinyobjloader, as vertices and triangles.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/core/limits.h"
#include "rubble/error.h"

namespace rubble {

/// A triangle mesh; triangles index vertices and wind as the file does.
struct TriangleMesh {
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> triangles;
};

/// Reads an OBJ file (polygons are triangulated), scaling every vertex by `scale`. The text is
/// checked first, line by line: numbers that do not parse (`nan`, `inf`, stray bytes) or do not
/// fit a float, `v` lines with the wrong count of coordinates, face indices that are not whole
/// numbers, are 0, overflow or name a vertex that does not exist, unknown statements, and
/// meshes beyond the limits of host/core/limits.h. Errors are BadInput at `where` (the scene field that named the
/// file) with the file and line: those, a missing or unreadable file, no faces, coordinates
/// that are not finite once scaled.
Result<TriangleMesh> loadObjMesh(const std::string& path, float scale, const std::string& where);

/// The same from the text of an OBJ file; `path` names it in errors.
Result<TriangleMesh> parseObjMesh(const std::string& text, const std::string& path, float scale,
                                  const std::string& where);

} // namespace rubble
