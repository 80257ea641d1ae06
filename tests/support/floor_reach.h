// tests/support/floor_reach.h: how far the bodies of a world reach into its static planes,
// judged by each body's lowest point (its shape's hull corners, or its radius, at its pose) and
// not by its centre: a crate whose centre is above the floor may still have sunk into it. On the
// particle path a box is the particles that fill it, a box with its corners rounded.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/world.h"

namespace rubble::test {

/// The signed distance of a body's lowest point from the plane n.x = offset (world frame, n
/// unit), m: negative when the body reaches below it. Planes reach nowhere (+infinity). With
/// `particleRadius` r > 0 a box is its particles of radius r, whose centres fill the box shrunk
/// by r (the particle path's voxels: r is half the spacing).
inline double lowestAbove(const World& world, std::uint32_t body, glm::dvec3 n, double offset,
                          double particleRadius = 0.0) {
    const ShapeGeometry& shape = world.shape(world.bodyShape(body));
    const BodyState b = world.body(body);
    const glm::dvec3 centre(b.position);
    const glm::dquat q(b.orientation);
    const double above = glm::dot(n, centre) - offset;
    switch (shape.type) {
    case ShapeType::Plane:
        return std::numeric_limits<double>::infinity();
    case ShapeType::Sphere:
        return above - double(shape.radius);
    default:
        break;
    }
    double lowest = std::numeric_limits<double>::infinity();
    if (shape.type == ShapeType::Box && (particleRadius > 0.0 || shape.vertices.empty())) {
        // The box's corners, or its corner particles' centres and their radius.
        const glm::dvec3 h = glm::dvec3(shape.halfExtents) - particleRadius;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 c((corner & 1 ? 1 : -1) * h.x, (corner & 2 ? 1 : -1) * h.y,
                               (corner & 4 ? 1 : -1) * h.z);
            lowest = std::min(lowest, glm::dot(n, centre + q * c) - offset - particleRadius);
        }
        return lowest;
    }
    for (const glm::vec3& v : shape.vertices)
        lowest = std::min(lowest, glm::dot(n, centre + q * glm::dvec3(v)) - offset);
    return lowest;
}

/// The deepest reach of any dynamic body below any static plane of the world.
struct FloorReach {
    double depth = 0.0;     ///< m below the plane; 0 when no body reaches below one
    std::uint32_t body = 0; ///< the deepest body (0 when none reaches below)
    std::string name;       ///< its name
};

/// Over every dynamic body and static plane; `particleRadius` as for lowestAbove.
inline FloorReach deepestBelowFloor(const World& world, double particleRadius = 0.0) {
    FloorReach deepest;
    for (std::uint32_t p = 0; p < world.bodyCount(); ++p) {
        const ShapeGeometry& plane = world.shape(world.bodyShape(p));
        if (!world.body(p).isStatic || plane.type != ShapeType::Plane) continue;
        const BodyState pose = world.body(p);
        const glm::dvec3 n = glm::dquat(pose.orientation) * glm::dvec3(plane.normal);
        const double offset = double(plane.offset) + glm::dot(n, glm::dvec3(pose.position));
        for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
            if (world.body(i).isStatic) continue;
            const double below = -lowestAbove(world, i, n, offset, particleRadius);
            if (below > deepest.depth) deepest = {below, i, world.bodyName(i)};
        }
    }
    return deepest;
}

} // namespace rubble::test
