// host/viewer/shape_mesh.cpp: shapes to triangles for drawing.
#include "host/viewer/shape_mesh.h"

#include <cmath>

namespace rubble::viewer {
namespace {

constexpr int kSphereSlices = 24; // around the y axis
constexpr int kSphereStacks = 14; // pole to pole

// Newell's method: robust for any planar polygon, and its direction follows the winding.
glm::vec3 polygonNormal(const std::vector<glm::vec3>& v, const std::vector<std::uint32_t>& face) {
    glm::vec3 n(0.0f);
    for (std::size_t i = 0; i < face.size(); ++i) {
        const glm::vec3 a = v[face[i]];
        const glm::vec3 b = v[face[(i + 1) % face.size()]];
        n += glm::vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                       (a.x - b.x) * (a.y + b.y));
    }
    const float len = glm::length(n);
    return len > 0.0f ? n / len : glm::vec3(0, 1, 0);
}

RenderMesh fromPolygons(const std::vector<glm::vec3>& vertices,
                        const std::vector<std::vector<std::uint32_t>>& faces) {
    RenderMesh m;
    for (const std::vector<std::uint32_t>& face : faces) {
        if (face.size() < 3) continue;
        const glm::vec3 n = polygonNormal(vertices, face);
        const auto base = std::uint32_t(m.vertices.size());
        for (std::uint32_t i : face) m.vertices.push_back({vertices[i], n});
        // A fan over the face's own copy of its corners keeps the normal flat.
        for (std::uint32_t k = 1; k + 1 < face.size(); ++k)
            m.indices.insert(m.indices.end(), {base, base + k, base + k + 1});
    }
    return m;
}

RenderMesh fromTriangles(const std::vector<glm::vec3>& vertices,
                         const std::vector<glm::uvec3>& triangles) {
    RenderMesh m;
    m.vertices.reserve(3 * triangles.size());
    for (const glm::uvec3& t : triangles) {
        const glm::vec3 a = vertices[t.x], b = vertices[t.y], c = vertices[t.z];
        const glm::vec3 cr = glm::cross(b - a, c - a);
        const float len = glm::length(cr);
        if (!(len > 0.0f)) continue; // degenerate: nothing to see
        const glm::vec3 n = cr / len;
        const auto base = std::uint32_t(m.vertices.size());
        m.vertices.insert(m.vertices.end(), {{a, n}, {b, n}, {c, n}});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    return m;
}

// A sphere, or with halfHeight > 0 a capsule: the sphere's upper half raised by halfHeight, its
// lower half lowered, and the equator drawn twice so that a band of cylinder joins them.
RenderMesh sphere(float radius, float halfHeight = 0.0f) {
    RenderMesh m;
    const float pi = 3.14159265358979f;
    const int equator = kSphereStacks / 2;
    const int rings = halfHeight > 0.0f ? kSphereStacks + 1 : kSphereStacks;
    for (int k = 0; k <= rings; ++k) {
        const int i = halfHeight > 0.0f && k > equator ? k - 1 : k;
        const glm::vec3 shift(0.0f, k <= equator ? halfHeight : -halfHeight, 0.0f);
        const float theta = pi * float(i) / kSphereStacks; // from +y down
        for (int j = 0; j <= kSphereSlices; ++j) {
            const float phi = 2.0f * pi * float(j) / kSphereSlices;
            const glm::vec3 n(std::sin(theta) * std::sin(phi), std::cos(theta),
                              std::sin(theta) * std::cos(phi));
            m.vertices.push_back({radius * n + shift, n});
        }
    }
    const std::uint32_t row = kSphereSlices + 1;
    for (std::uint32_t i = 0; i < std::uint32_t(rings); ++i)
        for (std::uint32_t j = 0; j < kSphereSlices; ++j) {
            const std::uint32_t a = i * row + j, b = a + row;
            m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
    return m;
}

} // namespace

RenderMesh buildRenderMesh(const ShapeGeometry& shape) {
    switch (shape.type) {
    case ShapeType::Box: // the world gives a box its hull's corners and faces, as a convex
    case ShapeType::Convex:
        return fromPolygons(shape.vertices, shape.faces);
    case ShapeType::Mesh:
        return shape.meshTriangles.empty() ? fromPolygons(shape.vertices, shape.faces)
                                           : fromTriangles(shape.meshVertices, shape.meshTriangles);
    case ShapeType::Sphere:
        return sphere(shape.radius);
    case ShapeType::Capsule:
        return sphere(shape.radius, shape.halfHeight);
    case ShapeType::Plane:
        return {};
    }
    return {};
}

} // namespace rubble::viewer
