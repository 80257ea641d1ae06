// host/io/quality.cpp: end-state figures of a run, from poses and velocities alone.
#include "host/io/quality.h"

#include <algorithm>
#include <vector>

namespace rubble {
namespace {

// The lowest signed distance of a body's surface to a plane (negative: below it).
double lowestDistance(const ShapeGeometry& s, const TrajectoryRow& r, glm::dvec3 n, double offset) {
    const glm::dvec3 centre(r.position);
    switch (s.type) {
    case ShapeType::Sphere:
        return glm::dot(n, centre) - offset - s.radius;
    case ShapeType::Plane:
        return 0.0;
    case ShapeType::Capsule: {
        // The lower end of the segment, less the radius.
        const glm::dvec3 axis = glm::dquat(r.orientation) * glm::dvec3(0.0, s.halfHeight, 0.0);
        return glm::dot(n, centre) - std::abs(glm::dot(n, axis)) - offset - s.radius;
    }
    default: {
        double lowest = 1e300;
        const glm::dquat q(r.orientation);
        for (const glm::vec3& v : s.vertices)
            lowest = std::min(lowest, glm::dot(n, centre + q * glm::dvec3(v)) - offset);
        return lowest;
    }
    }
}

} // namespace

QualityReport assessQuality(std::span<const QualityBody> bodies,
                            std::span<const TrajectoryRow> now,
                            std::span<const TrajectoryRow> before, double interval) {
    QualityReport q;
    // The floors: static planes, found once (a scene has a few among many bodies).
    std::vector<std::size_t> planes;
    for (std::size_t j = 0; j < bodies.size(); ++j)
        if (bodies[j].isStatic && bodies[j].shape->type == ShapeType::Plane) planes.push_back(j);
    std::size_t dynamic = 0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const QualityBody& b = bodies[i];
        if (b.isStatic) continue;
        ++dynamic;
        const TrajectoryRow& r = now[i];
        const glm::dvec3 v(r.linearVelocity), w(r.angularVelocity);
        const glm::dmat3 rot = glm::mat3_cast(glm::dquat(r.orientation));
        const glm::dmat3 inertiaWorld = rot * b.inertia * glm::transpose(rot);
        q.kineticEnergy += 0.5 * b.mass * glm::dot(v, v) + 0.5 * glm::dot(w, inertiaWorld * w);
        q.maxSpeed = std::max(q.maxSpeed, glm::length(v));
        if (glm::length(v) > kMovingSpeed) ++q.moving;
        if (!before.empty() && interval > 0.0)
            q.meanDrift += glm::length(glm::dvec3(r.position) - glm::dvec3(before[i].position)) / interval;
        for (const std::size_t j : planes) {
            const QualityBody& p = bodies[j];
            const glm::dvec3 n = glm::dquat(now[j].orientation) * glm::dvec3(p.shape->normal);
            const double offset = double(p.shape->offset) + glm::dot(n, glm::dvec3(now[j].position));
            if (glm::dot(n, glm::dvec3(r.position)) - offset < 0.0) ++q.sunk;
            q.floorPenetration = std::max(q.floorPenetration, -lowestDistance(*b.shape, r, n, offset));
        }
    }
    if (dynamic > 0) q.meanDrift /= double(dynamic);
    return q;
}

} // namespace rubble
