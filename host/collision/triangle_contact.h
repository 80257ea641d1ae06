// host/collision/triangle_contact.h: contacts of one static triangle (level_mesh.h) with a
// sphere, a capsule or a convex hull, in the mesh's frame, for stage narrowPhase of the CPU
// pipeline (level_collision.h gathers them per pair). Triangles are two-sided; internal edges
// (EdgeKind Flat and Concave, and Convex ones outside the arc between the two faces' normals)
// never give a contact normal other than the face's, so that bodies slide over the seams of a
// mesh as over one surface.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "host/collision/capsule_contact.h"
#include "host/geometry/half_edge.h"
#include "host/geometry/level_mesh.h"

namespace rubble {

/// One contact with a triangle, mesh frame.
struct TriangleContact {
    glm::vec3 position{0.0f};           ///< midway between the surfaces, m
    float depth = 0.0f;                 ///< penetration along the normal, m (< 0: a gap)
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< unit, from the triangle to the other body
    std::uint32_t feature = 0;          ///< the triangle and the point, stable while they touch
};

/// A polygon corner being clipped, with a tag that names the features that made it (stable
/// while the same features touch, for the contact's feature id).
struct TaggedPoint {
    glm::vec3 position{0.0f};
    std::uint32_t tag = 0;
};

/// A convex hull placed in the mesh's frame, with what the triangle tests read of it.
struct PlacedHull {
    const HalfEdgeMesh* mesh = nullptr; ///< the hull, in its own frame
    glm::mat3 rotation{1.0f};           ///< hull frame to mesh frame
    glm::vec3 translation{0.0f};        ///< m
    std::vector<glm::vec3> vertices;    ///< mesh frame
    std::vector<glm::vec3> faceNormals; ///< mesh frame, unit
    std::vector<float> faceOffsets;     ///< m
    std::vector<glm::vec3> edgeOrigins, edgeDirections; ///< one per undirected edge, mesh frame
    glm::vec3 centroid{0.0f};
    std::vector<TaggedPoint> polygon, clipped; ///< clipping scratch
};

/// Places `hull` by the rotation and translation of its frame in the mesh's (reusing `out`).
void placeHull(const HalfEdgeMesh& hull, const glm::mat3& rotation, glm::vec3 translation,
               PlacedHull& out);

/// True when `normal` (unit, from the triangle outwards) may be a contact normal at the
/// triangle's feature furthest along it: the face, a Boundary edge, a Convex edge within the arc
/// between the two faces' normals, or a vertex where one of its edges allows it. `side` (+1 or
/// -1) is the side of the triangle the other body is on.
bool normalAllowed(const LevelTriangle& t, float side, glm::vec3 normal);

/// The closest point of the triangle to p, and the feature it lies on: 0..2 vertex k, 3..5 edge
/// k - 3 (from v[k] to v[k + 1]), 6 the face (Ericson, "Real-Time Collision Detection", 5.1.5).
glm::vec3 closestOnTriangle(const LevelTriangle& t, glm::vec3 p, int& feature);

/// A sphere of radius r at c: one contact within the margin.
void collideTriangleSphere(const LevelTriangle& t, std::uint32_t index, glm::vec3 c, float r,
                           float margin, std::vector<TriangleContact>& out);

/// A capsule (segment s, radius r): the segment's ends clipped to the triangle when it lies on
/// the face, otherwise the closest points; each within the margin.
void collideTriangleCapsule(const LevelTriangle& t, std::uint32_t index, const Segment& s,
                            float r, float margin, std::vector<TriangleContact>& out);

/// A convex hull: separating axes (the triangle's normal, the hull's face normals, the cross
/// products of the hull's edges with the triangle's Boundary edges and its edges convex from the
/// hull's side), the least-penetrating axis that normalAllowed accepts (faces preferred), then
/// the incident face clipped to the triangle, or the triangle to the hull's face, or the edges'
/// closest points. Nothing when an axis separates by more than the margin. Internal edges are
/// not tested as axes: what touches past them lies over the neighbour, and what this triangle
/// reports is clipped to its own prism.
void collideTriangleHull(const LevelTriangle& t, std::uint32_t index, PlacedHull& hull,
                         float margin, std::vector<TriangleContact>& out);

} // namespace rubble
