// host/geometry/half_edge.h: convex polyhedra as half-edge meshes (physics report 3.2.1), with
// coplanar faces merged, their invariants checked, and support points by hill climbing (3.2.2).
// The narrow phase (rubble/shared/narrow_phase.h, over the flattened hulls of
// host/collision/hull_data.h) reads them; built once per shape.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/geometry/convex_hull.h"
#include "rubble/error.h"

namespace rubble {

/// One directed edge. Half-edges 2k and 2k+1 are twins, so k numbers the undirected edges.
struct HalfEdge {
    std::uint32_t origin = 0; ///< the vertex it leaves
    std::uint32_t face = 0;   ///< the face on its left, seen from outside
    std::uint32_t next = 0;   ///< the next half-edge counter-clockwise around that face
    std::uint32_t twin = 0;   ///< the same edge walked the other way, in the adjacent face
};

/// One face: its plane and one of its half-edges.
struct HalfEdgeFace {
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< unit, out of the solid, shape frame
    float offset = 0.0f;                ///< dot(normal, x) on the plane, m: the hull's support
    std::uint32_t edge = 0;             ///< a half-edge of the face
};

/// An undirected edge as the edge query reads it, precomputed so that the inner loop touches
/// one record: the half-edge 2k it stands for, its first vertex and direction, the normals of the
/// faces on both sides and their cross product (the edge's arc on the Gauss map).
struct HalfEdgeEdge {
    glm::vec3 origin{0.0f};      ///< vertex of half-edge 2k, m
    glm::vec3 direction{0.0f};   ///< to the other vertex, m (not normalised)
    glm::vec3 normalLeft{0.0f};  ///< face of half-edge 2k, unit
    glm::vec3 normalRight{0.0f}; ///< face of half-edge 2k+1, unit
    glm::vec3 arc{0.0f};         ///< cross(normalRight, normalLeft)
};

/// A closed convex polyhedron as a half-edge mesh, in the shape frame.
struct HalfEdgeMesh {
    std::vector<glm::vec3> vertices;
    std::vector<std::uint32_t> vertexEdge; ///< one half-edge leaving each vertex
    std::vector<HalfEdge> edges;           ///< twins at 2k and 2k+1
    std::vector<HalfEdgeFace> faces;
    std::vector<HalfEdgeEdge> edgeRecords; ///< one per undirected edge k
    /// The edges' Gauss-map arcs as nine rows of edgeCount() floats (arc x, y, z, left normal
    /// x, y, z, right normal x, y, z), so that the arc test runs over many edges at once.
    std::vector<float> edgeArcs;
    /// The vertices next to vertex v, in turn about it, are neighbours[neighbourStart[v]] up to
    /// neighbours[neighbourStart[v + 1]]: the half-edge ring flattened for hill climbing.
    std::vector<std::uint32_t> neighbourStart, neighbours;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; ///< axis-aligned bounds of the vertices, m
    glm::vec3 centroid{0.0f};                   ///< mean of the vertices, strictly inside, m

    std::uint32_t vertexCount() const { return std::uint32_t(vertices.size()); }
    std::uint32_t edgeCount() const { return std::uint32_t(edges.size() / 2); }
    std::uint32_t faceCount() const { return std::uint32_t(faces.size()); }
    bool empty() const { return vertices.empty(); }
};

/// Adjacent faces are merged when their normals differ by less than this angle (rad)...
inline constexpr float kMergeAngle = 0.01f;
/// ...and every vertex of the merged face lies within this fraction of the hull's bounding
/// radius of one plane.
inline constexpr float kMergeDistance = 1e-5f;
/// The invariant checks allow this fraction of the bounding radius for planarity and convexity.
inline constexpr float kShapeTolerance = 1e-4f;
/// Merging visits the vertices of two groups of faces while they hold at most this many
/// together; larger groups are merged by a bound on their thickness that never under-estimates.
inline constexpr std::size_t kExactMergeVertices = 256;
/// Meshes with vertices x faces up to this are checked (and their face planes placed) against
/// every vertex; larger ones edge by edge and by hill climbing, in near-linear time.
inline constexpr double kWholeMeshCheckLimit = 4e6;

/// Builds the half-edge mesh of a closed convex polyhedron given as polygons (triangles are
/// fine) wound counter-clockwise seen from outside. Adjacent coplanar faces are merged (within
/// kMergeAngle and kMergeDistance), vertices left between two collinear edges are dropped, and
/// unused vertices removed; then every invariant is checked (checkHalfEdgeMesh). Errors:
/// BadInput at `where` naming the broken invariant (an open surface, an edge used twice in one
/// direction, a non-convex or non-planar face, a wrong Euler characteristic, inward winding).
Result<HalfEdgeMesh> buildHalfEdgeMesh(const ConvexPolygons& polygons, const std::string& where);

/// Checks a half-edge mesh: twins paired and walking the other way, face loops closed and
/// covering every half-edge once, V - E + F = 2, faces planar and convex (within kShapeTolerance
/// of the bounding radius), every face plane a supporting plane with the vertex centroid
/// strictly below: tested against every vertex when V F <= kWholeMeshCheckLimit, else against
/// the far corner of each neighbouring face (every edge convex). Errors: BadInput at `where`
/// naming the first broken invariant.
Status checkHalfEdgeMesh(const HalfEdgeMesh& mesh, const std::string& where);

/// The vertex furthest along `direction` (any length), by hill climbing over the edges from
/// `start`: moves to the neighbour that improves most until none does. Exact on a convex mesh.
std::uint32_t supportVertex(const HalfEdgeMesh& mesh, glm::vec3 direction, std::uint32_t start = 0);

/// The same by visiting every vertex (the first of equals wins); for tests and tiny meshes.
std::uint32_t supportVertexBruteForce(const HalfEdgeMesh& mesh, glm::vec3 direction);

/// The vertex indices of a face, counter-clockwise seen from outside.
std::vector<std::uint32_t> faceVertices(const HalfEdgeMesh& mesh, std::uint32_t face);

} // namespace rubble
