// host/geometry/convex_hull.h: the convex hull of a point set, by Qhull, as ordered polygons.
// Shapes of type convex and mesh start here; host/geometry/half_edge builds on the result.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rubble/error.h"

namespace rubble {

/// A closed convex polyhedron: its vertices and its faces, each a convex polygon of vertex
/// indices ordered counter-clockwise seen from outside.
struct ConvexPolygons {
    std::vector<glm::vec3> vertices;
    std::vector<std::vector<std::uint32_t>> faces;

    /// The faces as triangles (fans), counter-clockwise seen from outside.
    std::vector<glm::uvec3> triangles() const;
};

/// The convex hull of points (m, any frame). Facets that Qhull finds coplanar within its
/// round-off are merged into one polygon. Fails with BadInput at `where` when there are fewer
/// than 4 points, a point is not finite, or the points are coplanar or collinear.
Result<ConvexPolygons> computeConvexHull(std::span<const glm::vec3> points,
                                         const std::string& where);

} // namespace rubble
