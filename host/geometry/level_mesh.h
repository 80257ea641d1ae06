// host/geometry/level_mesh.h: a static triangle mesh as the narrow phase collides with it: its
// triangles with their normals and the kind of each edge (from the triangles' adjacency, for
// internal edges), and their hierarchy (triangle_bvh.h). Built once per static mesh shape.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/geometry/obj_mesh.h"
#include "host/geometry/triangle_bvh.h"
#include "rubble/error.h"

namespace rubble {

/// What lies across a triangle's edge, seen from the side its normal points to.
enum class EdgeKind : std::uint8_t {
    Boundary, ///< no neighbour, or more than one: contacts may take any normal out of the edge
    Flat,     ///< a coplanar neighbour: the edge is internal, contacts take the face normal
    Convex,   ///< the neighbour bends away: normals between the two faces' are allowed
    Concave,  ///< the neighbour bends towards the normal: internal, the neighbour collides
};

/// One triangle: corners counter-clockwise about `normal`.
struct LevelTriangle {
    std::array<glm::vec3, 3> v{};
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< unit, by the file's winding, mesh frame
    /// Edge k runs from v[k] to v[(k + 1) % 3].
    std::array<EdgeKind, 3> edges{EdgeKind::Boundary, EdgeKind::Boundary, EdgeKind::Boundary};
    /// The neighbour's normal across edge k, turned to agree with this triangle's winding
    /// (Convex and Concave edges).
    std::array<glm::vec3, 3> neighbourNormal{};
    std::uint32_t source = 0; ///< index of the triangle in the file's mesh
};

/// A static mesh's triangles (degenerate ones left out) and their hierarchy, in the mesh frame.
struct LevelMesh {
    std::vector<LevelTriangle> triangles;
    TriangleBvh bvh;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; ///< m
};

/// Neighbours whose normals differ by less than this angle (rad) are coplanar.
inline constexpr float kFlatEdgeAngle = 0.01f;

/// Builds the level mesh of a triangle mesh: vertices at the same position are one, an edge
/// shared by exactly two triangles gets its kind from their normals (the neighbour's turned to
/// agree with the triangle's winding when the two wind the shared edge the same way), any other
/// edge is a boundary. Errors: BadInput at `where` when no triangle has an area.
Result<LevelMesh> buildLevelMesh(const TriangleMesh& mesh, const std::string& where);

} // namespace rubble
