// host/geometry/level_mesh.cpp: a static mesh's triangles, edge kinds and hierarchy.
#include "host/geometry/level_mesh.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace rubble {
namespace {

// Vertex ids by position: equal positions share the smallest index among them.
std::vector<std::uint32_t> weldByPosition(const std::vector<glm::vec3>& vertices) {
    std::vector<std::uint32_t> order(vertices.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    const auto key = [&](std::uint32_t i) {
        return std::tuple(vertices[i].x, vertices[i].y, vertices[i].z, i);
    };
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    std::vector<std::uint32_t> id(vertices.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
        const bool same = k > 0 && vertices[order[k]] == vertices[order[k - 1]];
        id[order[k]] = same ? id[order[k - 1]] : order[k];
    }
    return id;
}

// One directed edge of a kept triangle, keyed by its welded ends (low, high).
struct EdgeUse {
    std::uint32_t low, high, triangle, edge;
    bool forward; // walks low to high
};

} // namespace

Result<LevelMesh> buildLevelMesh(const TriangleMesh& mesh, const std::string& where) {
    LevelMesh level;
    const std::vector<std::uint32_t> id = weldByPosition(mesh.vertices);
    std::vector<glm::uvec3> kept;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 tri = mesh.triangles[t];
        LevelTriangle lt;
        lt.v = {mesh.vertices[tri.x], mesh.vertices[tri.y], mesh.vertices[tri.z]};
        const glm::vec3 n = glm::cross(lt.v[1] - lt.v[0], lt.v[2] - lt.v[0]);
        const float area2 = glm::length(n);
        // Slivers have no normal to speak of.
        const float longest = std::max({glm::length(lt.v[1] - lt.v[0]),
                                        glm::length(lt.v[2] - lt.v[1]),
                                        glm::length(lt.v[0] - lt.v[2])});
        if (!(area2 > 1e-6f * longest * longest)) continue;
        lt.normal = n / area2;
        lt.source = t;
        level.triangles.push_back(lt);
        kept.emplace_back(id[tri.x], id[tri.y], id[tri.z]);
    }
    if (level.triangles.empty())
        return makeError(ErrorKind::BadInput, where, "the mesh has no triangle with an area");

    // Edges by their welded ends: two uses of one edge make neighbours.
    std::vector<EdgeUse> uses;
    uses.reserve(3 * kept.size());
    for (std::uint32_t t = 0; t < kept.size(); ++t)
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t a = kept[t][int(k)], b = kept[t][int((k + 1) % 3)];
            uses.push_back({std::min(a, b), std::max(a, b), t, k, a < b});
        }
    std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
        return std::tie(x.low, x.high, x.triangle, x.edge) <
               std::tie(y.low, y.high, y.triangle, y.edge);
    });
    const float flatCosine = std::cos(kFlatEdgeAngle);
    for (std::size_t s = 0; s < uses.size();) {
        std::size_t e = s + 1;
        while (e < uses.size() && uses[e].low == uses[s].low && uses[e].high == uses[s].high) ++e;
        if (e - s == 2) {
            for (int side = 0; side < 2; ++side) {
                const EdgeUse& self = uses[s + std::size_t(side)];
                const EdgeUse& other = uses[s + std::size_t(1 - side)];
                LevelTriangle& t = level.triangles[self.triangle];
                const LevelTriangle& u = level.triangles[other.triangle];
                // Wound the same way round the edge: the neighbour faces the other way.
                const glm::vec3 nu = self.forward != other.forward ? u.normal : -u.normal;
                const glm::vec3 far = u.v[(other.edge + 2) % 3];
                const float bend = glm::dot(t.normal, far - t.v[self.edge]);
                t.neighbourNormal[self.edge] = nu;
                t.edges[self.edge] = glm::dot(t.normal, nu) >= flatCosine ? EdgeKind::Flat
                                     : bend < 0.0f                        ? EdgeKind::Convex
                                                                          : EdgeKind::Concave;
            }
        }
        s = e;
    }

    std::vector<glm::vec3> corners;
    corners.reserve(3 * level.triangles.size());
    std::vector<glm::uvec3> indices;
    indices.reserve(level.triangles.size());
    for (const LevelTriangle& t : level.triangles) {
        const auto base = std::uint32_t(corners.size());
        corners.insert(corners.end(), t.v.begin(), t.v.end());
        indices.emplace_back(base, base + 1, base + 2);
    }
    level.bvh = TriangleBvh(corners, indices);
    level.boundsMin = level.boundsMax = corners.front();
    for (const glm::vec3& c : corners) {
        level.boundsMin = glm::min(level.boundsMin, c);
        level.boundsMax = glm::max(level.boundsMax, c);
    }
    return level;
}

} // namespace rubble
