// host/geometry/shape.h: a shape as the pipelines use it, built once from its ShapeDesc with the
// centre of mass at the origin of its frame.
#pragma once

#include <memory>
#include <string>

#include <glm/glm.hpp>

#include "host/core/mass_properties.h"
#include "host/geometry/convex_hull.h"
#include "host/geometry/half_edge.h"
#include "host/geometry/level_mesh.h"
#include "host/geometry/obj_mesh.h"
#include "rubble/error.h"
#include "rubble/scene.h"
#include "rubble/shape.h"

namespace rubble {

/// A built shape. Box, convex and mesh shapes carry their convex hull, as polygons and as a
/// half-edge mesh for the narrow phase; a mesh also keeps its own triangles (for voxelising,
/// where concavity matters). All vertices are in the body frame: the file's frame moved so that
/// the centre of mass is at the origin.
struct Shape {
    std::string name;
    ShapeType type = ShapeType::Box;
    glm::vec3 halfExtents{0.0f};  ///< box, m
    float radius = 0.0f;          ///< sphere and capsule, m
    float halfHeight = 0.0f;      ///< capsule: the segment from (0, -h, 0) to (0, h, 0), m
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< plane, unit, out of the solid
    float offset = 0.0f;          ///< plane, m
    ConvexPolygons hull;          ///< box, convex, mesh
    HalfEdgeMesh halfEdge;        ///< the hull with coplanar faces merged: box, convex, mesh
    TriangleMesh mesh;            ///< mesh only
    MassProperties unitMass;      ///< at 1 kg/m^3, centre at the origin (planes: zero)
    glm::vec3 centreShift{0.0f};  ///< the file's centre of mass, subtracted from its vertices, m
    float boundingRadius = 0.0f;  ///< largest distance of the shape from its origin, m
    /// mesh used by a static body: its triangles for the narrow phase (shared between copies).
    std::shared_ptr<const LevelMesh> level;
};

/// How the world's bodies use a shape: what buildShape must make of a mesh.
struct ShapeUse {
    bool level = false;  ///< a static body has it: the mesh's triangles collide (LevelMesh)
    bool moving = true;  ///< a dynamic or kinematic body has it: the mesh collides as its hull
};

/// Builds a shape: the hull (Qhull) for convex and mesh shapes, the mass properties (closed
/// forms, or polyhedral integration of the hull; a closed mesh uses its own triangles so that a
/// concave mesh gets its real centre of mass), the shift to the centre of mass, and the hull's
/// half-edge mesh. A mesh with `use.level` also gets its LevelMesh; one used by static bodies only
/// may enclose no volume (a flat or open level), and then keeps the file's frame and has no hull,
/// as does a heightfield, which keeps its grid's frame. Errors: BadInput at the shape's field for
/// degenerate hulls or a half-edge mesh that breaks its invariants, or a level mesh without a
/// triangle of some area.
Result<Shape> buildShape(const ShapeDesc& desc, ShapeUse use = {});

/// The shape as a host program sees it (World::shape): its hull, its mesh, its sizes.
ShapeGeometry geometryOf(const Shape& shape);

/// The 8 corners and 6 faces of a box with the given half extents, centred on the origin.
ConvexPolygons boxPolygons(glm::vec3 halfExtents);

/// True when every edge of the mesh is shared by exactly two triangles wound in opposite
/// directions (vertices at the same position count as one), so that it bounds a volume.
bool isClosedMesh(const TriangleMesh& mesh);

} // namespace rubble
