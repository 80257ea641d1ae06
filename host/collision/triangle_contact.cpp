// host/collision/triangle_contact.cpp: the host's side of a static triangle's contacts (stage
// narrowPhase, CPU): a triangle's shared record and a hull placed in the mesh's frame for
// rubble/shared/triangle_contact.h; see triangle_contact.h.
#include "host/collision/triangle_contact.h"

#include <algorithm>

#include "host/core/math.h"

namespace rubble {

shared::MeshTriangle meshTriangleOf(const LevelTriangle& t, std::uint32_t index) {
    shared::MeshTriangle r{};
    for (std::size_t k = 0; k < 3; ++k) {
        r.v[k] = toFloat4(t.v[k]);
        r.neighbourNormal[k] = toFloat4(t.neighbourNormal[k]);
        r.edges |= std::uint32_t(t.edges[k]) << (2 * k);
    }
    r.normal = toFloat4(t.normal);
    r.index = index;
    return r;
}

void placeHull(const HalfEdgeMesh& hull, const glm::mat3& rotation, glm::vec3 translation,
               PlacedHull& out) {
    out.mesh = &hull;
    // The topology in the shared layout (own frame), for face loops and hill climbing.
    out.ownVertices.resize(hull.vertices.size());
    for (std::size_t i = 0; i < hull.vertices.size(); ++i)
        out.ownVertices[i] = toFloat4(hull.vertices[i]);
    out.neighbourStart.assign(hull.neighbourStart.begin(), hull.neighbourStart.end());
    out.neighbours.assign(hull.neighbours.begin(), hull.neighbours.end());
    out.halfEdges.resize(hull.edges.size());
    for (std::size_t h = 0; h < hull.edges.size(); ++h) {
        const HalfEdge& e = hull.edges[h];
        out.halfEdges[h] = shared::HullHalfEdge{e.origin, e.face, e.next, e.twin};
    }
    out.faceEdges.resize(hull.faces.size());
    std::size_t largestFace = 0;
    for (std::size_t f = 0; f < hull.faces.size(); ++f) {
        out.faceEdges[f] = hull.faces[f].edge;
        // The face's corners, counted round its loop.
        std::size_t corners = 0;
        std::uint32_t h = hull.faces[f].edge;
        do {
            ++corners;
            h = hull.edges[h].next;
        } while (h != hull.faces[f].edge);
        largestFace = std::max(largestFace, corners);
    }
    // Placed once, read by every triangle.
    out.vertices.resize(hull.vertices.size());
    for (std::size_t i = 0; i < hull.vertices.size(); ++i)
        out.vertices[i] = toFloat4(rotation * hull.vertices[i] + translation);
    out.faces.resize(hull.faces.size());
    for (std::size_t f = 0; f < hull.faces.size(); ++f) {
        const glm::vec3 normal = rotation * hull.faces[f].normal;
        const glm::vec3 corner = toVec3(out.vertices[hull.edges[hull.faces[f].edge].origin]);
        out.faces[f] = toFloat4(normal, glm::dot(normal, corner));
    }
    out.edgeOrigins.resize(hull.edgeRecords.size());
    out.edgeDirections.resize(hull.edgeRecords.size());
    for (std::size_t e = 0; e < hull.edgeRecords.size(); ++e) {
        out.edgeOrigins[e] = toFloat4(rotation * hull.edgeRecords[e].origin + translation);
        out.edgeDirections[e] = toFloat4(rotation * hull.edgeRecords[e].direction);
    }
    out.polygon.resize(largestFace + RUBBLE_TRIANGLE_EXTRA_CONTACTS + 1);
    out.clipped.resize(out.polygon.size());

    shared::PlacedHull& v = out.view;
    v = shared::PlacedHull{};
    v.hull.vertices = out.ownVertices.data();
    v.hull.neighbourStart = out.neighbourStart.data();
    v.hull.neighbours = out.neighbours.data();
    v.hull.edges = out.halfEdges.data();
    v.hull.faceEdge = out.faceEdges.data();
    v.hull.vertexCount = hull.vertexCount();
    v.hull.edgeCount = std::uint32_t(hull.edgeRecords.size());
    v.hull.faceCount = hull.faceCount();
    v.place = shared::RigidTransform{toShared(rotation), toFloat4(translation)};
    v.toHull = toShared(glm::transpose(rotation));
    v.centroid = toFloat4(rotation * hull.centroid + translation);
    v.vertices = out.vertices.data();
    v.faces = out.faces.data();
    v.edgeOrigins = out.edgeOrigins.data();
    v.edgeDirections = out.edgeDirections.data();
    v.polygon = out.polygon.data();
    v.clipped = out.clipped.data();
}

} // namespace rubble
