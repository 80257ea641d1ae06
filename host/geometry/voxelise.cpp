// host/geometry/voxelise.cpp: shapes into particles by ray parity on a uniform grid.
#include "host/geometry/voxelise.h"

#include <algorithm>
#include <cmath>

namespace rubble {
namespace {

// Ray directions skewed off every axis and diagonal, so that rays from grid-aligned centres do
// not run along the edges of axis-aligned faces.
const glm::vec3 kRays[3] = {glm::normalize(glm::vec3(1.0f, 0.1234567f, 0.0543210f)),
                            glm::normalize(glm::vec3(-0.0712345f, 1.0f, 0.1654321f)),
                            glm::normalize(glm::vec3(0.1357913f, -0.0864213f, 1.0f))};

// Moller-Trumbore: does the ray o + t d, t > 0, cross triangle (a, b, c)?
bool rayCrosses(glm::vec3 o, glm::vec3 d, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::vec3 e1 = b - a, e2 = c - a;
    const glm::vec3 p = glm::cross(d, e2);
    const float det = glm::dot(e1, p);
    if (std::fabs(det) < 1e-12f) return false;
    const float inv = 1.0f / det;
    const glm::vec3 s = o - a;
    const float u = glm::dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) return false;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(d, q) * inv;
    if (v < 0.0f || u + v > 1.0f) return false;
    return glm::dot(e2, q) * inv > 0.0f;
}

} // namespace

bool insideTriangles(glm::vec3 point, const std::vector<glm::vec3>& vertices,
                     const std::vector<glm::uvec3>& triangles) {
    int votes = 0;
    for (const glm::vec3& d : kRays) {
        int crossings = 0;
        for (const glm::uvec3& t : triangles)
            crossings += rayCrosses(point, d, vertices[t.x], vertices[t.y], vertices[t.z]) ? 1 : 0;
        votes += crossings % 2;
    }
    return votes >= 2;
}

VoxelCost voxelCost(const Shape& shape, float spacing) {
    if (shape.type == ShapeType::Plane) return {};
    glm::dvec3 extent(2.0 * double(shape.radius));
    if (shape.type == ShapeType::Capsule) extent.y += 2.0 * double(shape.halfHeight);
    double triangles = 0;
    if (shape.type != ShapeType::Sphere && shape.type != ShapeType::Capsule) {
        const bool ownMesh = shape.type == ShapeType::Mesh && !shape.mesh.triangles.empty();
        const std::vector<glm::vec3>& vertices = ownMesh ? shape.mesh.vertices : shape.hull.vertices;
        glm::dvec3 lo(vertices.front()), hi(vertices.front());
        for (const glm::vec3& v : vertices) {
            lo = glm::min(lo, glm::dvec3(v));
            hi = glm::max(hi, glm::dvec3(v));
        }
        extent = hi - lo;
        if (ownMesh) {
            triangles = double(shape.mesh.triangles.size());
        } else {
            for (const auto& face : shape.hull.faces) triangles += double(face.size()) - 2.0;
        }
    }
    VoxelCost c;
    c.cells = 1.0;
    for (int k = 0; k < 3; ++k) c.cells *= std::max(1.0, std::ceil(extent[k] / double(spacing) - 1e-4));
    c.rayTests = 3.0 * c.cells * triangles;
    return c;
}

std::vector<glm::vec3> voxeliseShape(const Shape& shape, float spacing, bool surfaceOnly) {
    if (shape.type == ShapeType::Plane) return {};
    // The surface to test against, and its bounds.
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> triangles;
    glm::vec3 lo(0.0f), hi(0.0f);
    if (shape.type == ShapeType::Sphere || shape.type == ShapeType::Capsule) {
        hi = glm::vec3(shape.radius, shape.radius + shape.halfHeight, shape.radius);
        lo = -hi;
    } else {
        const bool ownMesh = shape.type == ShapeType::Mesh && !shape.mesh.triangles.empty();
        vertices = ownMesh ? shape.mesh.vertices : shape.hull.vertices;
        triangles = ownMesh ? shape.mesh.triangles : shape.hull.triangles();
        lo = hi = vertices.front();
        for (const glm::vec3& v : vertices) {
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
    }
    const glm::vec3 extent = hi - lo, centre = 0.5f * (lo + hi);
    const glm::ivec3 n = glm::max(glm::ivec3(glm::ceil(extent / spacing - 1e-4f)), glm::ivec3(1));
    auto cellCentre = [&](int x, int y, int z) {
        return centre + spacing * (glm::vec3(x, y, z) - 0.5f * glm::vec3(n - 1));
    };
    auto inside = [&](glm::vec3 p) {
        if (shape.type == ShapeType::Sphere) return glm::length(p) <= shape.radius;
        if (shape.type == ShapeType::Capsule) {
            // Within the radius of the segment from -y to +y.
            const float y = std::clamp(p.y, -shape.halfHeight, shape.halfHeight);
            return glm::length(p - glm::vec3(0.0f, y, 0.0f)) <= shape.radius;
        }
        return insideTriangles(p, vertices, triangles);
    };
    // Inside flags with a one-cell border of outside around the grid.
    const glm::ivec3 m = n + 2;
    std::vector<std::uint8_t> in(std::size_t(m.x) * m.y * m.z, 0);
    auto at = [&](int x, int y, int z) { return (std::size_t(z + 1) * m.y + (y + 1)) * m.x + (x + 1); };
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) in[at(x, y, z)] = inside(cellCentre(x, y, z)) ? 1 : 0;

    std::vector<glm::vec3> centres;
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                if (!in[at(x, y, z)]) continue;
                const bool interior = in[at(x - 1, y, z)] && in[at(x + 1, y, z)] &&
                                      in[at(x, y - 1, z)] && in[at(x, y + 1, z)] &&
                                      in[at(x, y, z - 1)] && in[at(x, y, z + 1)];
                if (surfaceOnly && interior) continue;
                centres.push_back(cellCentre(x, y, z));
            }
    if (centres.empty()) centres.push_back(glm::vec3(0.0f));
    return centres;
}

} // namespace rubble
