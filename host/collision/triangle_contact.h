// host/collision/triangle_contact.h: what the CPU's narrow phase hands the shared triangle
// contacts (rubble/shared/triangle_contact.h, triangle_hull_contact.h, which the device runs too):
// a static triangle's record (level_mesh.h) and a hull placed in the mesh's frame;
// level_collision.h collides them per pair. Triangles are two-sided; internal
// edges (EdgeKind Flat and Concave, and Convex ones outside the arc between the two faces' normals)
// never give a contact normal other than the face's, so that bodies slide over the seams of a
// mesh as over one surface.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "host/collision/capsule_contact.h"
#include "host/geometry/half_edge.h"
#include "host/geometry/level_mesh.h"
#include "rubble/shared/triangle_hull_contact.h"

namespace rubble {

/// One contact with a triangle, mesh frame.
struct TriangleContact {
    glm::vec3 position{0.0f};           ///< midway between the surfaces, m
    float depth = 0.0f;                 ///< penetration along the normal, m (< 0: a gap)
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< unit, from the triangle to the other body
    std::uint32_t feature = 0;          ///< the triangle and the point, stable while they touch
};

/// A convex hull placed in the mesh's frame: the shared view (rubble/shared/triangle_contact.h)
/// and the arrays it reads, the hull's topology in the shared layout and its placed vertices,
/// faces and edges (placed once per pair, read by every triangle).
struct PlacedHull {
    const HalfEdgeMesh* mesh = nullptr; ///< the hull, in its own frame
    std::vector<shared::float4> ownVertices;
    std::vector<std::uint32_t> neighbourStart, neighbours, faceEdges;
    std::vector<shared::HullHalfEdge> halfEdges;
    std::vector<shared::float4> vertices; ///< mesh frame
    std::vector<shared::float4> faces;    ///< unit normal (xyz) and offset (w), mesh frame
    std::vector<shared::float4> edgeOrigins, edgeDirections; ///< one per undirected edge
    std::vector<shared::TaggedPoint> polygon, clipped;       ///< clipping scratch
    shared::PlacedHull view{};
};

/// The shared record of a triangle of index `index`.
shared::MeshTriangle meshTriangleOf(const LevelTriangle& t, std::uint32_t index);

/// Places `hull` by the rotation and translation of its frame in the mesh's (reusing `out`).
void placeHull(const HalfEdgeMesh& hull, const glm::mat3& rotation, glm::vec3 translation,
               PlacedHull& out);

} // namespace rubble
