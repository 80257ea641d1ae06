// host/scene/height_field.h: heightfield shapes of a scene file: the grid from `heights` or a
// 16-bit greyscale PNG, checked, and turned into the triangles of a static mesh.
#pragma once

#include <string>

#include "host/scene/json_reader.h"
#include "rubble/scene.h"

namespace rubble {

/// Reads a heightfield shape's fields (`heights` or `file` with `height_scale`, and `spacing`)
/// into d.heightField, and its grid's triangles into d.points and d.triangles (type Mesh).
/// `baseDir` is the scene's folder, against which `file` is resolved. Errors: BadInput at the
/// field for a height that is not finite, rows of different lengths, fewer than 2 x 2 heights, a
/// spacing that is not positive, a PNG that cannot be read or is not 16-bit greyscale, a grid
/// past the mesh limits of host/core/limits.h.
Status readHeightField(const ObjectReader& s, const std::string& baseDir, ShapeDesc& d);

/// The grid's vertices and triangles (two to a cell, wound counter-clockwise seen from +y),
/// centred on the origin in x and z. The grid must be valid (at least 2 x 2, heights sized).
void heightFieldTriangles(const HeightFieldDesc& grid, std::vector<glm::vec3>& points,
                          std::vector<glm::uvec3>& triangles);

} // namespace rubble
