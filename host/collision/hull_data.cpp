// host/collision/hull_data.cpp: flattening a world's shapes for the SAT narrow phase.
#include "host/collision/hull_data.h"

#include <algorithm>

#include "host/core/assert.h"
#include "host/core/math.h"

namespace rubble {

HullData flattenHulls(std::span<const Shape> shapes) {
    HullData d;
    for (const Shape& s : shapes) {
        shared::HullShape r{};
        r.boundingRadius = s.boundingRadius;
        r.vertexStart = std::uint32_t(d.vertices.size());
        r.halfEdgeStart = std::uint32_t(d.halfEdges.size());
        r.edgeStart = std::uint32_t(d.edges.size());
        r.faceStart = std::uint32_t(d.faces.size());
        if (s.type == ShapeType::Sphere) {
            r.kind = RUBBLE_SHAPE_SPHERE;
            r.radius = s.radius;
        } else if (s.type == ShapeType::Plane) {
            r.kind = RUBBLE_SHAPE_PLANE;
            r.plane = toFloat4(s.normal, s.offset);
        } else if (s.type == ShapeType::Capsule) {
            // Its bounds make the broad phase's box.
            r.kind = RUBBLE_SHAPE_CAPSULE;
            r.radius = s.radius;
            r.halfHeight = s.halfHeight;
            r.boundsMax = toFloat4(glm::vec3(s.radius, s.halfHeight + s.radius, s.radius));
            r.boundsMin = toFloat4(-glm::vec3(s.radius, s.halfHeight + s.radius, s.radius));
        } else if (s.halfEdge.empty()) {
            // Level geometry without a hull (static only): its bounds make the broad phase's box;
            // its contacts are its triangles' (level_collision.h).
            RUBBLE_ASSERT(s.level != nullptr);
            r.kind = RUBBLE_SHAPE_HULL;
            r.boundsMin = toFloat4(s.level->boundsMin);
            r.boundsMax = toFloat4(s.level->boundsMax);
            r.centroid = toFloat4(0.5f * (s.level->boundsMin + s.level->boundsMax));
        } else {
            RUBBLE_ASSERT(collidesAsHull(s.type));
            const HalfEdgeMesh& m = s.halfEdge;
            r.kind = RUBBLE_SHAPE_HULL;
            r.boundsMin = toFloat4(m.boundsMin);
            r.boundsMax = toFloat4(m.boundsMax);
            r.centroid = toFloat4(m.centroid);
            r.vertexCount = m.vertexCount();
            r.edgeCount = m.edgeCount();
            r.faceCount = m.faceCount();
            for (std::uint32_t f = 0; f < m.faceCount(); ++f)
                d.largestFace = std::max(d.largestFace, std::uint32_t(faceVertices(m, f).size()));
            const auto neighbourBase = std::uint32_t(d.neighbours.size());
            for (std::uint32_t v = 0; v < m.vertexCount(); ++v) {
                d.vertices.push_back(toFloat4(m.vertices[v]));
                d.vertexEdges.push_back(m.vertexEdge[v]);
                d.neighbourStart.push_back(neighbourBase + m.neighbourStart[v]);
            }
            d.neighbours.insert(d.neighbours.end(), m.neighbours.begin(), m.neighbours.end());
            for (const HalfEdge& e : m.edges)
                d.halfEdges.push_back(shared::HullHalfEdge{e.origin, e.face, e.next, e.twin});
            for (const HalfEdgeFace& f : m.faces) {
                d.faces.push_back(toFloat4(f.normal, f.offset));
                d.faceEdges.push_back(f.edge);
            }
            for (const HalfEdgeEdge& e : m.edgeRecords)
                d.edges.push_back(shared::HullEdge{toFloat4(e.origin), toFloat4(e.direction),
                                                   toFloat4(e.normalLeft), toFloat4(e.normalRight),
                                                   toFloat4(e.arc)});
        }
        d.shapes.push_back(r);
    }
    // The end of the last vertex's ring.
    d.neighbourStart.push_back(std::uint32_t(d.neighbours.size()));
    return d;
}

shared::HullArrays hullArraysOf(const HullData& data) {
    shared::HullArrays a{};
    a.vertices = data.vertices.data();
    a.vertexEdges = data.vertexEdges.data();
    a.neighbourStart = data.neighbourStart.data();
    a.neighbours = data.neighbours.data();
    a.halfEdges = data.halfEdges.data();
    a.faces = data.faces.data();
    a.faceEdges = data.faceEdges.data();
    a.edges = data.edges.data();
    return a;
}

} // namespace rubble
