// host/collision/sat.cpp: face and edge queries of the separating axis test, with the Gauss-map
// pruning of edge pairs (Gregorius, GDC 2013; physics report 3.3, 3.3.1). Part of CPU stage
// narrowPhase; no allocation.
#include "host/collision/sat.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rubble {
namespace {

constexpr float kLowest = -std::numeric_limits<float>::max();

// Arcs AB and CD of the Gauss maps cross (a, b: normals of A's edge; c, d: negated normals of
// B's edge, since the Minkowski difference turns B inside out) when c and d lie on opposite
// sides of the plane through a and b, a and b on opposite sides of the plane through c and d,
// and the crossing is on the hemisphere of the arcs, not at its antipode:
//   (c . b x a)(d . b x a) < 0,  (a . d x c)(b . d x c) < 0,  (c . b x a)(b . d x c) > 0.
// queryEdgeDirections evaluates it for batches of this many of A's edges at a time.
constexpr std::size_t kArcBatch = 64;

// The unit axis eA x eB turned out of A (away from its centroid through A's edge point), or
// std::nullopt for near-parallel edges.
std::optional<glm::vec3> edgeAxis(glm::vec3 pointA, glm::vec3 dirA, glm::vec3 dirB,
                                  glm::vec3 centroidA) {
    const glm::vec3 n = glm::cross(dirA, dirB);
    const float n2 = glm::dot(n, n);
    const float limit = kParallelSine * kParallelSine * glm::dot(dirA, dirA) * glm::dot(dirB, dirB);
    if (!(n2 > limit)) return std::nullopt;
    const glm::vec3 axis = n * (1.0f / std::sqrt(n2));
    return glm::dot(axis, pointA - centroidA) < 0.0f ? -axis : axis;
}

// Support-point separation with the hill climbs seeded and updated by the caller.
float separationAlongFrom(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                          glm::vec3 axis, std::uint32_t& startA, std::uint32_t& startB) {
    startA = supportVertex(a, axis, startA);
    startB = supportVertex(b, bInA.rotateInverse(-axis), startB);
    return glm::dot(axis, bInA.apply(b.vertices[startB])) - glm::dot(axis, a.vertices[startA]);
}

} // namespace

FaceQuery queryFace(const HalfEdgeMesh& a, std::uint32_t face, const HalfEdgeMesh& b,
                    const Transform& bInA, std::uint32_t startVertex) {
    const HalfEdgeFace& f = a.faces[face];
    const std::uint32_t v = supportVertex(b, bInA.rotateInverse(-f.normal),
                                          startVertex < b.vertexCount() ? startVertex : 0);
    return FaceQuery{glm::dot(f.normal, bInA.apply(b.vertices[v])) - f.offset, face, v};
}

FaceQuery queryFaceDirections(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                              float stopAbove) {
    FaceQuery best;
    // Neighbouring faces have nearby support points: each climb starts at the last one found.
    std::uint32_t start = 0;
    for (std::uint32_t f = 0; f < a.faceCount(); ++f) {
        const HalfEdgeFace& face = a.faces[f];
        start = supportVertex(b, bInA.rotateInverse(-face.normal), start);
        const float s = glm::dot(face.normal, bInA.apply(b.vertices[start])) - face.offset;
        if (s > best.separation) {
            best = FaceQuery{s, f, start};
            if (s > stopAbove) break;
        }
    }
    return best;
}

EdgeQuery queryEdgeDirections(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                              float stopAbove) {
    EdgeQuery best;
    const std::size_t edgesA = a.edgeCount();
    const float* arcX = a.edgeArcs.data();
    const float *arcY = arcX + edgesA, *arcZ = arcY + edgesA;
    const float *leftX = arcZ + edgesA, *leftY = leftX + edgesA, *leftZ = leftY + edgesA;
    const float *rightX = leftZ + edgesA, *rightY = rightX + edgesA, *rightZ = rightY + edgesA;
    std::array<std::uint8_t, kArcBatch> crossing;
    for (std::uint32_t kb = 0; kb < b.edgeCount(); ++kb) {
        // B's edge in A's frame, its normals negated for the Minkowski difference A - B;
        // cross(d, c) = cross(-nR, -nL) is B's own arc, rotated.
        const HalfEdgeEdge& eb = b.edgeRecords[kb];
        const glm::vec3 c = -bInA.rotate(eb.normalLeft), d = -bInA.rotate(eb.normalRight);
        const glm::vec3 dxc = bInA.rotate(eb.arc);
        // The edge itself only once an arc crosses (most of B's edges meet none).
        bool placed = false;
        glm::vec3 pointB(0.0f), dirB(0.0f);
        for (std::size_t first = 0; first < edgesA; first += kArcBatch) {
            // The arc test for a batch of A's edges without branches, so that it vectorises;
            // then the few that pass.
            const std::size_t count = std::min(kArcBatch, edgesA - first);
            for (std::size_t i = 0; i < count; ++i) {
                const std::size_t k = first + i;
                const float cba = c.x * arcX[k] + c.y * arcY[k] + c.z * arcZ[k];
                const float dba = d.x * arcX[k] + d.y * arcY[k] + d.z * arcZ[k];
                const float adc = leftX[k] * dxc.x + leftY[k] * dxc.y + leftZ[k] * dxc.z;
                const float bdc = rightX[k] * dxc.x + rightY[k] * dxc.y + rightZ[k] * dxc.z;
                crossing[i] = (cba * dba < 0.0f) & (adc * bdc < 0.0f) & (cba * bdc > 0.0f);
            }
            for (std::size_t i = 0; i < count; ++i) {
                if (!crossing[i]) continue;
                if (!placed) {
                    pointB = bInA.apply(eb.origin);
                    dirB = bInA.rotate(eb.direction);
                    placed = true;
                }
                const auto ka = std::uint32_t(first + i);
                const HalfEdgeEdge& ea = a.edgeRecords[ka];
                const std::optional<glm::vec3> axis =
                    edgeAxis(ea.origin, ea.direction, dirB, a.centroid);
                if (!axis) continue;
                // On a Minkowski face both edges are support features: their points project
                // to the supports, so no support query is needed.
                const float s = glm::dot(*axis, pointB - ea.origin);
                if (s > best.separation) {
                    best = EdgeQuery{s, ka, kb, *axis};
                    if (s > stopAbove) return best;
                }
            }
        }
    }
    return best;
}

EdgeQuery queryEdgeDirectionsUnpruned(const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                                      const Transform& bInA, float stopAbove) {
    EdgeQuery best;
    for (std::uint32_t kb = 0; kb < b.edgeCount(); ++kb) {
        const HalfEdgeEdge& eb = b.edgeRecords[kb];
        const glm::vec3 dirB = bInA.rotate(eb.direction);
        for (std::uint32_t ka = 0; ka < a.edgeCount(); ++ka) {
            const HalfEdgeEdge& ea = a.edgeRecords[ka];
            const std::optional<glm::vec3> axis =
                edgeAxis(ea.origin, ea.direction, dirB, a.centroid);
            if (!axis) continue;
            for (const glm::vec3 u : {*axis, -*axis}) {
                // The climbs start at the edges' own vertices.
                std::uint32_t startA = a.edges[2 * ka].origin, startB = b.edges[2 * kb].origin;
                const float s = separationAlongFrom(a, b, bInA, u, startA, startB);
                if (s > best.separation) {
                    best = EdgeQuery{s, ka, kb, u};
                    if (s > stopAbove) return best;
                }
            }
        }
    }
    return best;
}

std::optional<glm::vec3> edgePairAxis(const HalfEdgeMesh& a, std::uint32_t edgeA,
                                      const HalfEdgeMesh& b, std::uint32_t edgeB,
                                      const Transform& bInA) {
    const HalfEdgeEdge& ea = a.edgeRecords[edgeA];
    return edgeAxis(ea.origin, ea.direction, bInA.rotate(b.edgeRecords[edgeB].direction),
                    a.centroid);
}

float separationAlong(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                      glm::vec3 axis) {
    std::uint32_t startA = 0, startB = 0;
    return separationAlongFrom(a, b, bInA, axis, startA, startB);
}

SatResult runSat(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA, float margin,
                 const SatHint& hint, bool pruneEdges) {
    SatResult r;
    const Transform aInB = inverse(bInA);
    auto settle = [&r](SatFeature feature, float s, std::uint32_t ia, std::uint32_t ib,
                       glm::vec3 axis, std::uint32_t vertex = 0) {
        r.feature = feature;
        r.separation = s;
        r.indexA = ia;
        r.indexB = ib;
        r.axis = axis;
        r.vertex = vertex;
    };

    // Last step's axis first: a pair that stays apart is settled by one or two support queries.
    if (hint.feature == SatFeature::FaceA && hint.indexA < a.faceCount()) {
        const FaceQuery q = queryFace(a, hint.indexA, b, bInA, hint.vertex);
        settle(SatFeature::FaceA, q.separation, hint.indexA, 0, a.faces[hint.indexA].normal,
               q.vertex);
    } else if (hint.feature == SatFeature::FaceB && hint.indexB < b.faceCount()) {
        const FaceQuery q = queryFace(b, hint.indexB, a, aInB, hint.vertex);
        settle(SatFeature::FaceB, q.separation, 0, hint.indexB,
               -bInA.rotate(b.faces[hint.indexB].normal), q.vertex);
    } else if (hint.feature == SatFeature::Edges && hint.indexA < a.edgeCount() &&
               hint.indexB < b.edgeCount()) {
        if (const auto axis = edgePairAxis(a, hint.indexA, b, hint.indexB, bInA))
            settle(SatFeature::Edges, separationAlong(a, b, bInA, *axis), hint.indexA, hint.indexB,
                   *axis);
    }
    if (r.feature != SatFeature::None && r.separation > margin) {
        r.separated = true;
        return r;
    }
    r.feature = SatFeature::None;

    r.faceA = queryFaceDirections(a, b, bInA, margin);
    settle(SatFeature::FaceA, r.faceA.separation, r.faceA.face, 0, a.faces[r.faceA.face].normal,
           r.faceA.vertex);
    if (r.separation > margin) {
        r.separated = true;
        return r;
    }
    r.faceB = queryFaceDirections(b, a, aInB, margin);
    if (r.faceB.separation > r.separation)
        settle(SatFeature::FaceB, r.faceB.separation, 0, r.faceB.face,
               -bInA.rotate(b.faces[r.faceB.face].normal), r.faceB.vertex);
    if (r.separation > margin) {
        r.separated = true;
        return r;
    }
    r.edges = pruneEdges ? queryEdgeDirections(a, b, bInA, margin)
                         : queryEdgeDirectionsUnpruned(a, b, bInA, margin);
    if (r.edges.separation > r.separation)
        settle(SatFeature::Edges, r.edges.separation, r.edges.edgeA, r.edges.edgeB, r.edges.axis);
    r.separated = r.separation > margin;
    return r;
}

std::optional<SatResult> findSeparation(const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                                        const Transform& bInA) {
    SatResult r = runSat(a, b, bInA);
    if (r.separated) return std::nullopt;
    return r;
}

} // namespace rubble
