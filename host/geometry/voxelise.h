// host/geometry/voxelise.h: a shape as particles (Harada, GPU Gems 3 ch. 29; Bell et al. 2005):
// a uniform grid around it, each cell whose centre is inside the shape becomes a sphere of the
// grid spacing. Made once per shape at load; used by both particle pipelines.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "host/geometry/shape.h"

namespace rubble {

/// Particle centres of a shape, body frame, m. The grid has cells of `spacing` (m) and is
/// centred on the shape's bounding box. Spheres are tested analytically; boxes and convex
/// shapes through their hull's triangles; meshes through their own triangles, so a concave
/// mesh keeps its hollows: a cell is inside when rays from its centre cross the surface an odd
/// number of times (the majority of three skewed rays, so that a ray grazing an edge cannot
/// flip it). With `surfaceOnly`, cells whose six neighbours are all inside are left out: they
/// can only touch anything after a particle-deep penetration. A shape smaller than one cell
/// gets one particle at its origin. Planes have none.
std::vector<glm::vec3> voxeliseShape(const Shape& shape, float spacing, bool surfaceOnly);

/// The cost of voxelising a shape at `spacing` (m), known before doing it: the grid's cells and
/// the ray-triangle tests (cells times the triangles tested, 3 rays each).
struct VoxelCost {
    double cells = 0;
    double rayTests = 0;
};
VoxelCost voxelCost(const Shape& shape, float spacing);

/// True when a point (shape frame, m) is inside the closed triangle surface by the ray parity
/// rule above.
bool insideTriangles(glm::vec3 point, const std::vector<glm::vec3>& vertices,
                     const std::vector<glm::uvec3>& triangles);

} // namespace rubble
