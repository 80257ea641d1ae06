// host/collision/hull_contact.cpp: hull-hull manifolds for CPU stage narrowPhase: feature choice
// with hysteresis, face clipping (Sutherland-Hodgman), edge contacts (Gregorius 2015).
#include "host/collision/hull_contact.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "host/collision/clip.h"

namespace rubble {
namespace {

// A feature replaces the preferred one only when it is shallower by more than this fraction of
// the preferred separation plus an absolute tolerance (m): faces of A over faces of B over edges.
constexpr float kRelativeFaceTolerance = 0.05f;
constexpr float kRelativeEdgeTolerance = 0.10f;
constexpr float kAbsoluteTolerance = 0.0025f;

// A cached edge pair's axis may turn by about 0.5 degrees (cosine) before the full test runs
// again, as much as a face normal under kReuseRotation; support points along it this far (m)
// below its edges' points mean the axis has left the pair's Gauss-map arcs.
constexpr float kReuseAxisCosine = 0.99996f;
constexpr float kSupportTolerance = 1e-4f;

// Faces up to this many vertices (incident plus reference) clip in stack buffers.
constexpr std::size_t kInlineClipVertices = 64;

bool clearlyLarger(float x, float preferred, float relative) {
    return x > preferred + relative * std::fabs(preferred) + kAbsoluteTolerance;
}

std::uint32_t loopLength(const HalfEdgeMesh& m, std::uint32_t face) {
    std::uint32_t n = 0, h = m.faces[face].edge;
    do {
        ++n;
        h = m.edges[h].next;
    } while (h != m.faces[face].edge);
    return n;
}

// The incident face: of the faces around the deepest vertex, the one whose normal is most
// anti-parallel to the reference normal (mesh frame). Faces elsewhere on a round hull can be
// as anti-parallel yet far from the contact.
std::uint32_t incidentFace(const HalfEdgeMesh& mesh, glm::vec3 normal, std::uint32_t deepest) {
    const std::uint32_t first = mesh.vertexEdge[deepest];
    std::uint32_t best = mesh.edges[first].face, h = first;
    float lowest = glm::dot(mesh.faces[best].normal, normal);
    do {
        const std::uint32_t f = mesh.edges[h].face;
        const float d = glm::dot(mesh.faces[f].normal, normal);
        if (d < lowest) {
            lowest = d;
            best = f;
        }
        h = mesh.edges[mesh.edges[h].twin].next;
    } while (h != first);
    return best;
}

// Stack buffers for clipping, with a heap fallback for faces with many vertices.
class ClipBuffers {
  public:
    explicit ClipBuffers(std::size_t capacity) {
        if (capacity > kInlineClipVertices) {
            heapIn_.resize(capacity);
            heapOut_.resize(capacity);
            heapContacts_.resize(capacity);
        }
    }
    std::span<ClipVertex> in() {
        return heapIn_.empty() ? std::span(inlineIn_) : std::span(heapIn_);
    }
    std::span<ClipVertex> out() {
        return heapOut_.empty() ? std::span(inlineOut_) : std::span(heapOut_);
    }
    std::span<LocalContact> contacts() {
        return heapContacts_.empty() ? std::span(inlineContacts_) : std::span(heapContacts_);
    }

  private:
    std::array<ClipVertex, kInlineClipVertices> inlineIn_, inlineOut_;
    std::array<LocalContact, kInlineClipVertices> inlineContacts_;
    std::vector<ClipVertex> heapIn_, heapOut_;
    std::vector<LocalContact> heapContacts_;
};

// A face contact in the reference hull's frame: the incident polygon clipped by the side planes
// of the reference face, the points below its plane plus the margin, reduced to four.
ContactSet clipFaceContact(const HalfEdgeMesh& ref, const FaceQuery& query, const HalfEdgeMesh& inc,
                           const Transform& incInRef, float margin, ContactKind kind) {
    const HalfEdgeFace& rf = ref.faces[query.face];
    const std::uint32_t incFace =
        incidentFace(inc, incInRef.rotateInverse(rf.normal), query.vertex);
    ClipBuffers buffers(loopLength(inc, incFace) + loopLength(ref, query.face) + 1);
    std::span<ClipVertex> polygon = buffers.in(), scratch = buffers.out();

    // The incident polygon in the reference frame; each vertex tagged by its half-edge.
    std::size_t n = 0;
    std::uint32_t h = inc.faces[incFace].edge;
    do {
        polygon[n++] = ClipVertex{incInRef.apply(inc.vertices[inc.edges[h].origin]), 0, h, h};
        h = inc.edges[h].next;
    } while (h != inc.faces[incFace].edge);

    // Clip by a side plane through each reference edge: perpendicular to the face, or the
    // neighbouring face itself where it leans in under the edge (report 3.4.1), whichever is
    // tighter below the face, so that the points stay inside the reference hull.
    h = rf.edge;
    do {
        const HalfEdgeFace& next = ref.faces[ref.edges[ref.edges[h].twin].face];
        glm::vec3 side = next.normal;
        float offset = next.offset;
        if (glm::dot(next.normal, rf.normal) >= 0.0f) {
            const glm::vec3 v0 = ref.vertices[ref.edges[h].origin];
            const glm::vec3 v1 = ref.vertices[ref.edges[ref.edges[h].next].origin];
            side = glm::cross(v1 - v0, rf.normal);
            offset = glm::dot(side, v0);
        }
        n = clipPolygon(polygon.first(n), side, offset, h, scratch);
        std::swap(polygon, scratch);
        h = ref.edges[h].next;
    } while (n > 0 && h != rf.edge);

    // Keep what lies below the reference plane plus the margin, midway between the surfaces.
    std::span<LocalContact> candidates = buffers.contacts();
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const ClipVertex& v = polygon[i];
        const float s = glm::dot(rf.normal, v.position) - rf.offset;
        if (s > margin) continue;
        candidates[m++] = LocalContact{v.position - rf.normal * (0.5f * s), -s,
                                       makeFeatureId(kind, v.clipEdge, v.tag)};
    }
    ContactSet set;
    set.normal = rf.normal;
    std::array<std::uint32_t, kMaxContactPoints> keep{};
    const std::uint32_t kept = reduceContacts(candidates.first(m), rf.normal, keep);
    for (std::uint32_t i = 0; i < kept; ++i) set.points[set.count++] = candidates[keep[i]];
    return set;
}

// The closest points of the two edges, with the SAT's separation along their axis.
ContactSet edgeContact(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                       const EdgeQuery& q) {
    const HalfEdgeEdge& ea = a.edgeRecords[q.edgeA];
    const HalfEdgeEdge& eb = b.edgeRecords[q.edgeB];
    const glm::vec3 pb = bInA.apply(eb.origin);
    glm::vec3 ca, cb;
    closestPointsOnSegments(ea.origin, ea.origin + ea.direction, pb, pb + bInA.rotate(eb.direction),
                            ca, cb);
    ContactSet set;
    set.normal = q.axis;
    set.add((ca + cb) * 0.5f, -q.separation, makeFeatureId(ContactKind::Edges, q.edgeA, q.edgeB));
    return set;
}

// A face contact on B's face, made in B's frame and brought to A's frame, its normal turned to
// point from A to B.
ContactSet clipFaceContactOfB(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                              const FaceQuery& query, float margin) {
    ContactSet set = clipFaceContact(b, query, a, inverse(bInA), margin, ContactKind::FaceB);
    for (std::uint32_t i = 0; i < set.count; ++i)
        set.points[i].position = bInA.apply(set.points[i].position);
    set.normal = -bInA.rotate(set.normal);
    return set;
}

// True while a cached edge pair's axis at this pose is within kReuseAxisCosine of its axis at
// the reference, and the pair still spans a face of the Minkowski difference: along its axis the
// edges' own points are the support points (report 3.3.1), so that the separation the pair gives
// is the hulls' separation along that axis.
bool edgeAxisHolds(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                   const Transform& reference, const SatHint& edges) {
    const std::optional<glm::vec3> now = edgePairAxis(a, edges.indexA, b, edges.indexB, bInA);
    const std::optional<glm::vec3> then = edgePairAxis(a, edges.indexA, b, edges.indexB, reference);
    if (!now || !then || glm::dot(*now, *then) < kReuseAxisCosine) return false;
    const float byEdges = glm::dot(*now, bInA.apply(b.edgeRecords[edges.indexB].origin) -
                                             a.edgeRecords[edges.indexA].origin);
    return separationAlong(a, b, bInA, *now) >= byEdges - kSupportTolerance;
}

} // namespace

HullContact collideHulls(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                         float margin, const SatHint& hint) {
    HullContact r;
    const SatResult sat = runSat(a, b, bInA, margin, hint);
    if (sat.separated) {
        r.separated = true;
        r.feature = SatHint{sat.feature, sat.indexA, sat.indexB, sat.vertex};
        return r;
    }

    // Which feature makes the contacts: last step's face owner unless the other is clearly
    // shallower, and edges only when clearly shallower than both.
    const float sa = sat.faceA.separation, sb = sat.faceB.separation;
    const bool useB = hint.feature == SatFeature::FaceB
                          ? !clearlyLarger(sa, sb, kRelativeFaceTolerance)
                          : clearlyLarger(sb, sa, kRelativeFaceTolerance);
    const bool haveEdges = sat.edges.separation > -std::numeric_limits<float>::max();
    const bool useEdges =
        haveEdges && clearlyLarger(sat.edges.separation, useB ? sb : sa, kRelativeEdgeTolerance);
    // A fallback must be nearly as shallow as the best axis: a deeper axis would push the
    // bodies apart along the wrong direction.
    auto acceptable = [&](float s) {
        return !clearlyLarger(sat.separation, s, kRelativeEdgeTolerance);
    };
    auto tryFace = [&](bool ownerB) {
        if (!ownerB) {
            r.contacts = clipFaceContact(a, sat.faceA, b, bInA, margin, ContactKind::FaceA);
            r.feature = SatHint{SatFeature::FaceA, sat.faceA.face, 0, sat.faceA.vertex};
            return r.contacts.count > 0;
        }
        r.contacts = clipFaceContactOfB(a, b, bInA, sat.faceB, margin);
        r.feature = SatHint{SatFeature::FaceB, 0, sat.faceB.face, sat.faceB.vertex};
        return r.contacts.count > 0;
    };
    if (!useEdges) {
        if (tryFace(useB)) return r;
        // The clipped overlap held no point: the other face, then the edges, if good enough.
        if (acceptable(useB ? sa : sb) && tryFace(!useB)) return r;
        if (!haveEdges || !acceptable(sat.edges.separation)) {
            r.contacts = ContactSet{};
            return r;
        }
    }
    r.contacts = edgeContact(a, b, bInA, sat.edges);
    r.feature = SatHint{SatFeature::Edges, sat.edges.edgeA, sat.edges.edgeB};
    return r;
}

HullContact collideHullsFromFeature(const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                                    const Transform& bInA, const SatHint& feature, float margin) {
    HullContact r;
    r.feature = feature;
    if (feature.feature == SatFeature::FaceA && feature.indexA < a.faceCount()) {
        const FaceQuery q = queryFace(a, feature.indexA, b, bInA, feature.vertex);
        r.feature.vertex = q.vertex;
        r.separated = q.separation > margin;
        if (!r.separated) r.contacts = clipFaceContact(a, q, b, bInA, margin, ContactKind::FaceA);
        return r;
    }
    if (feature.feature == SatFeature::FaceB && feature.indexB < b.faceCount()) {
        const FaceQuery q = queryFace(b, feature.indexB, a, inverse(bInA), feature.vertex);
        r.feature.vertex = q.vertex;
        r.separated = q.separation > margin;
        if (!r.separated) r.contacts = clipFaceContactOfB(a, b, bInA, q, margin);
        return r;
    }
    if (feature.feature == SatFeature::Edges && feature.indexA < a.edgeCount() &&
        feature.indexB < b.edgeCount()) {
        if (const auto axis = edgePairAxis(a, feature.indexA, b, feature.indexB, bInA)) {
            const EdgeQuery q{separationAlong(a, b, bInA, *axis), feature.indexA, feature.indexB,
                              *axis};
            r.separated = q.separation > margin;
            if (!r.separated) r.contacts = edgeContact(a, b, bInA, q);
            return r;
        }
    }
    // No usable feature: the full test.
    return collideHulls(a, b, bInA, margin, feature);
}

HullContact collideHullsCached(const HalfEdgeMesh& a, const HalfEdgeMesh& b, const Transform& bInA,
                               HullPairCache& cache, float margin) {
    bool close = cache.reusable && cache.feature.feature != SatFeature::None &&
                 glm::length(bInA.translation - cache.reference.translation) <= kReuseDistance;
    for (int c = 0; close && c < 3; ++c) {
        const glm::vec3 d = glm::abs(bInA.rotation[c] - cache.reference.rotation[c]);
        close = std::max({d.x, d.y, d.z}) <= kReuseRotation;
    }
    // The axis of two nearly parallel edges swings with the slightest turn (by the turn over
    // the sine of their angle): it is the same axis only while it points the same way and the
    // edges are still the support features along it.
    if (close && cache.feature.feature == SatFeature::Edges)
        close = edgeAxisHolds(a, b, bInA, cache.reference, cache.feature);
    if (close) {
        const HullContact r = collideHullsFromFeature(a, b, bInA, cache.feature, margin);
        // A face that clipped to nothing while the hulls touch needs the full test.
        if (r.separated || r.contacts.count > 0) {
            cache.feature.vertex = r.feature.vertex; // the next climb starts here
            return r;
        }
    }
    HullContact r = collideHulls(a, b, bInA, margin, cache.feature);
    cache = HullPairCache{r.feature, bInA, true};
    return r;
}

} // namespace rubble
