// tests/unit/brute_force_sat.h: the separating-axis answer by brute force, for the property
// tests of the SAT and of the contact manifolds: every candidate axis tried on every vertex.
#pragma once

#include <algorithm>
#include <vector>

#include <glm/glm.hpp>

#include "transform.h"
#include "host/geometry/half_edge.h"
#include "rubble/shared/sat.h"

namespace rubble::test {

// Vertices as separate coordinate arrays, so that the projection loops vectorise.
struct Points {
    std::vector<float> x, y, z;
    explicit Points(const std::vector<glm::vec3>& v, const Transform& t = {}) {
        for (const glm::vec3& p : v) {
            const glm::vec3 q = t.apply(p);
            x.push_back(q.x);
            y.push_back(q.y);
            z.push_back(q.z);
        }
    }
    void project(glm::vec3 u, float& lo, float& hi) const {
        lo = 1e30f;
        hi = -1e30f;
        for (std::size_t i = 0; i < x.size(); ++i) {
            const float d = u.x * x[i] + u.y * y[i] + u.z * z[i];
            lo = std::min(lo, d);
            hi = std::max(hi, d);
        }
    }
};

// Brute force over candidate axes from all vertices' projections: the largest of
// max(minB - maxA, minA - maxB), that is of -h(A - B) over both orientations. Faces: every face
// normal of both hulls; edges: the cross product of every edge of a with every edge of b.
struct BruteForce {
    float faces = -1e30f, edges = -1e30f;
    float all() const { return std::max(faces, edges); }
};

inline BruteForce bruteForceSeparation(const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                                       const Transform& bInA) {
    const Points pa(a.vertices), pb(b.vertices, bInA);
    auto along = [&](glm::vec3 u) {
        float aMin, aMax, bMin, bMax;
        pa.project(u, aMin, aMax);
        pb.project(u, bMin, bMax);
        return std::max(bMin - aMax, aMin - bMax);
    };
    BruteForce r;
    for (const HalfEdgeFace& f : a.faces) r.faces = std::max(r.faces, along(f.normal));
    for (const HalfEdgeFace& f : b.faces) r.faces = std::max(r.faces, along(bInA.rotate(f.normal)));
    for (std::uint32_t i = 0; i < a.edgeCount(); ++i) {
        const glm::vec3 ea =
            a.vertices[a.edges[2 * i + 1].origin] - a.vertices[a.edges[2 * i].origin];
        for (std::uint32_t j = 0; j < b.edgeCount(); ++j) {
            const glm::vec3 eb = bInA.rotate(b.vertices[b.edges[2 * j + 1].origin] -
                                             b.vertices[b.edges[2 * j].origin]);
            const glm::vec3 c = glm::cross(ea, eb);
            if (glm::dot(c, c) <=
                RUBBLE_PARALLEL_SINE * RUBBLE_PARALLEL_SINE * glm::dot(ea, ea) * glm::dot(eb, eb))
                continue;
            r.edges = std::max(r.edges, along(glm::normalize(c)));
        }
    }
    return r;
}

} // namespace rubble::test
