// host/collision/sat.h: the separating axis test between two convex half-edge meshes, part of
// CPU stage narrowPhase (Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013;
// physics report 3.3). Pure: hulls and a relative pose in, a result by value out.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include <glm/glm.hpp>

#include "host/collision/transform.h"
#include "host/geometry/half_edge.h"

namespace rubble {

/// Which feature pair defines an axis.
enum class SatFeature : std::uint8_t {
    None,  ///< no axis yet
    FaceA, ///< a face normal of hull A
    FaceB, ///< a face normal of hull B
    Edges, ///< the cross product of an edge of A and an edge of B
};

/// Edge pairs closer to parallel than this sine of their angle give no axis: their cross
/// product is too short to normalise, and the face axes around them already cover it.
inline constexpr float kParallelSine = 1e-3f;

/// The best face of one hull: separation = dot(n, s) - offset, with s the other hull's support
/// point along -n (report 3.3), maximised over the faces.
struct FaceQuery {
    float separation = -std::numeric_limits<float>::max(); ///< m; > 0: a gap
    std::uint32_t face = 0;   ///< face of the hull whose faces were tried
    std::uint32_t vertex = 0; ///< the other hull's support vertex for that face
};

/// The best edge pair: separation along the normalised cross product, oriented out of A.
struct EdgeQuery {
    float separation = -std::numeric_limits<float>::max(); ///< m; > 0: a gap
    std::uint32_t edgeA = 0, edgeB = 0; ///< undirected edge indices k (half-edges 2k)
    glm::vec3 axis{0.0f};               ///< unit, A's frame, from A to B
};

/// A feature to test first, kept from last step (frame coherence).
struct SatHint {
    SatFeature feature = SatFeature::None;
    std::uint32_t indexA = 0, indexB = 0; ///< face of A or B, or edges of A and B
    std::uint32_t vertex = 0; ///< faces: the other hull's support vertex, where climbs start
};

/// The outcome of one separating axis test.
struct SatResult {
    bool separated = false;
    /// The separating axis found (separated), else the axis of least penetration.
    SatFeature feature = SatFeature::None;
    float separation = 0.0f;              ///< along that axis, m: > margin when separated
    std::uint32_t indexA = 0, indexB = 0; ///< as in SatHint
    std::uint32_t vertex = 0;             ///< faces: the other hull's support vertex
    glm::vec3 axis{0.0f};                 ///< unit, A's frame, from A to B
    FaceQuery faceA, faceB;               ///< the queries that ran (separation -max if not)
    EdgeQuery edges;
};

/// Face query: the faces of `a` against the support points of `b`; bInA is b's pose in a's
/// frame. Stops at the first face whose separation exceeds `stopAbove`.
FaceQuery queryFaceDirections(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                              float stopAbove = std::numeric_limits<float>::max());

/// Face query of one face of `a`: b's support point along the negated normal, climbed from
/// `startVertex` (any index; one past b's vertices starts at 0), and its signed distance to the
/// face plane.
FaceQuery queryFace(const HalfEdgeMesh& a, std::uint32_t face, const HalfEdgeMesh& b,
                    const Transform& bInA, std::uint32_t startVertex);

/// Edge query over the pairs whose Gauss-map arcs cross (report 3.3.1): only those pairs span
/// faces of the Minkowski difference, where the edges' own points are the support points.
/// Stops at the first pair whose separation exceeds `stopAbove`.
EdgeQuery queryEdgeDirections(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                              float stopAbove = std::numeric_limits<float>::max());

/// Edge query over every non-parallel pair, both orientations, separations from support
/// points: the slow reference the pruned query is tested and benchmarked against.
EdgeQuery queryEdgeDirectionsUnpruned(const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                                      const Transform& bInA,
                                      float stopAbove = std::numeric_limits<float>::max());

/// The axis of an edge pair (undirected edge indices of a and b) at b's pose in a's frame: the unit
/// cross product of the two edges turned out of a (away from its centroid through a's edge), or
/// std::nullopt when the edges are closer to parallel than kParallelSine.
std::optional<glm::vec3> edgePairAxis(const HalfEdgeMesh& a, std::uint32_t edgeA,
                                      const HalfEdgeMesh& b, std::uint32_t edgeB,
                                      const Transform& bInA);

/// Separation along an axis from support points: min over b minus max over a of the projections
/// on `axis` (unit, a's frame); > 0 when the axis separates them.
float separationAlong(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                      glm::vec3 axis);

/// The separating axis test: the hint's axis first, then the faces of a, the faces of b and the
/// pruned edge pairs, each stopping at the first axis whose separation exceeds `margin` (m).
/// Without a separating axis, the axis of least penetration (largest separation) wins, faces
/// before edges on ties. `pruneEdges` false uses the unpruned edge query (for benchmarks).
SatResult runSat(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                 float margin = 0.0f, const SatHint& hint = {}, bool pruneEdges = true);

/// The axis of least penetration; std::nullopt when a separating axis exists.
std::optional<SatResult> findSeparation(const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                                        const Transform& bInA);

} // namespace rubble
