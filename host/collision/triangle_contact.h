// host/collision/triangle_contact.h: contacts of one static triangle (level_mesh.h) with a
// sphere, a capsule or a convex hull, in the mesh's frame, for stage narrowPhase of the CPU
// pipeline (level_collision.h gathers them per pair), over the shared math of
// rubble/shared/triangle_contact.h that the device runs too. Triangles are two-sided; internal
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

/// A sphere of radius r at c: one contact within the margin (collideTriangleSphereItem).
void collideTriangleSphere(const LevelTriangle& t, std::uint32_t index, glm::vec3 c, float r,
                           float margin, std::vector<TriangleContact>& out);

/// A capsule (segment s, radius r): the segment's ends clipped to the triangle when it lies on
/// the face, otherwise the closest points; each within the margin (collideTriangleCapsuleItem).
void collideTriangleCapsule(const LevelTriangle& t, std::uint32_t index, const Segment& s, float r,
                            float margin, std::vector<TriangleContact>& out);

/// A convex hull placed by placeHull: separating axes, then a clipped face or the edges' closest
/// points (collideTriangleHullItem).
void collideTriangleHull(const LevelTriangle& t, std::uint32_t index, PlacedHull& hull,
                         float margin, std::vector<TriangleContact>& out);

} // namespace rubble
