// include/rubble/shape.h: a shape as a world built it (World::shape), for drawing and measuring.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rubble/scene.h"

namespace rubble {

/// A shape as the world built it, for drawing and measuring: body frame (the centre of mass at
/// the origin), m.
struct ShapeGeometry {
    std::string name;
    ShapeType type = ShapeType::Box;
    glm::vec3 halfExtents{0.0f};        ///< box
    float radius = 0.0f;                ///< sphere, capsule
    float halfHeight = 0.0f;            ///< capsule: its segment runs from -y to +y this far
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< plane: unit, out of the solid
    float offset = 0.0f;                ///< plane: dot(normal, x) = offset on its surface
    float boundingRadius = 0.0f;        ///< largest distance of the shape from its origin
    std::vector<glm::vec3> vertices;    ///< the convex hull's corners (box, convex, mesh)
    /// The hull's faces as corner indices, counter-clockwise seen from outside.
    std::vector<std::vector<std::uint32_t>> faces;
    std::vector<glm::vec3> meshVertices;    ///< mesh: its own vertices
    std::vector<glm::uvec3> meshTriangles;  ///< mesh: its own triangles, as the file winds them
};

} // namespace rubble
