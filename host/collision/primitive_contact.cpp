// host/collision/primitive_contact.cpp: sphere and plane contacts for CPU stage narrowPhase
// (Ericson 4.3, 5.1.2, 5.1.3, 5.2.2).
#include "host/collision/primitive_contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "host/collision/clip.h"

namespace rubble {
namespace {

// Sub-kinds of ContactKind::Primitive ids (the high field); the low field is the index.
enum PrimitiveFeature : std::uint32_t { kWhole = 0, kFace = 1, kEdge = 2, kVertex = 3 };

// Ids fitting in inline storage before the heap is used (hull-plane candidates).
constexpr std::size_t kInlineCandidates = 64;

// The closest point of segment p-q to c, and where on it (0 at p, 1 at q).
glm::vec3 closestOnSegment(glm::vec3 p, glm::vec3 q, glm::vec3 c, float& t) {
    const glm::vec3 d = q - p;
    const float d2 = glm::dot(d, d);
    t = d2 > 0.0f ? std::clamp(glm::dot(c - p, d) / d2, 0.0f, 1.0f) : 0.0f;
    return p + d * t;
}

} // namespace

ContactSet collideSpheres(glm::vec3 ca, float ra, glm::vec3 cb, float rb, float margin) {
    ContactSet set;
    const glm::vec3 d = cb - ca;
    const float dist = glm::length(d);
    const float s = dist - ra - rb;
    if (s > margin) return set;
    set.normal = dist > 1e-9f ? d / dist : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 onA = ca + set.normal * ra, onB = cb - set.normal * rb;
    set.add((onA + onB) * 0.5f, -s, makeFeatureId(ContactKind::Primitive, kWhole, 0));
    return set;
}

ContactSet collideHullSphere(const HalfEdgeMesh& hull, glm::vec3 c, float radius, float margin) {
    ContactSet set;
    // The face the centre is furthest above (or least below).
    std::uint32_t top = 0;
    float above = -std::numeric_limits<float>::max();
    for (std::uint32_t f = 0; f < hull.faceCount(); ++f) {
        const float s = glm::dot(hull.faces[f].normal, c) - hull.faces[f].offset;
        if (s > above) {
            above = s;
            top = f;
        }
    }
    if (above - radius > margin) return set;
    if (above <= 0.0f) {
        // The centre is inside: out through the face of least penetration.
        set.normal = hull.faces[top].normal;
        set.add(c - set.normal * (0.5f * (above + radius)), radius - above,
                makeFeatureId(ContactKind::Primitive, kFace, top));
        return set;
    }

    // Outside: the closest point lies on a face whose plane the centre is above.
    float best2 = std::numeric_limits<float>::max();
    glm::vec3 closest(0.0f), normal = hull.faces[top].normal;
    std::uint32_t kind = kFace, index = 0;
    for (std::uint32_t f = 0; f < hull.faceCount(); ++f) {
        const HalfEdgeFace& face = hull.faces[f];
        const float s = glm::dot(face.normal, c) - face.offset;
        if (s <= 0.0f) continue;
        const glm::vec3 projected = c - face.normal * s;
        bool inside = true;
        std::uint32_t h = face.edge;
        do {
            const glm::vec3 v0 = hull.vertices[hull.edges[h].origin];
            const glm::vec3 v1 = hull.vertices[hull.edges[hull.edges[h].next].origin];
            if (glm::dot(glm::cross(v1 - v0, face.normal), projected - v0) > 0.0f) {
                inside = false;
                float t = 0.0f;
                const glm::vec3 q = closestOnSegment(v0, v1, c, t);
                const float d2 = glm::dot(c - q, c - q);
                if (d2 < best2) {
                    best2 = d2;
                    closest = q;
                    normal = d2 > 1e-12f ? glm::normalize(c - q) : face.normal;
                    if (t <= 0.0f || t >= 1.0f) {
                        kind = kVertex;
                        index = t <= 0.0f ? hull.edges[h].origin
                                          : hull.edges[hull.edges[h].next].origin;
                    } else {
                        kind = kEdge;
                        index = h / 2;
                    }
                }
            }
            h = hull.edges[h].next;
        } while (h != face.edge);
        if (inside && s * s < best2) {
            // Over the face: its normal is exact, where c - projected loses digits.
            best2 = s * s;
            closest = projected;
            normal = face.normal;
            kind = kFace;
            index = f;
        }
    }
    const float dist = std::sqrt(best2);
    if (dist - radius > margin) return set;
    set.normal = normal;
    const glm::vec3 onSphere = c - set.normal * radius;
    set.add((closest + onSphere) * 0.5f, radius - dist,
            makeFeatureId(ContactKind::Primitive, kind, index));
    return set;
}

ContactSet collidePlaneSphere(glm::vec3 n, float offset, glm::vec3 c, float radius, float margin) {
    ContactSet set;
    const float s = glm::dot(n, c) - offset - radius;
    if (s > margin) return set;
    set.normal = n;
    set.add(c - n * (radius + 0.5f * s), -s, makeFeatureId(ContactKind::Primitive, kWhole, 0));
    return set;
}

ContactSet collidePlaneHull(glm::vec3 n, float offset, const HalfEdgeMesh& hull, float margin) {
    ContactSet set;
    set.normal = n;
    // The deepest vertex settles a hull that stays clear.
    const std::uint32_t deepest = supportVertex(hull, -n);
    if (glm::dot(n, hull.vertices[deepest]) - offset > margin) return set;

    std::array<LocalContact, kInlineCandidates> inlineCandidates;
    std::vector<LocalContact> heapCandidates;
    std::span<LocalContact> candidates(inlineCandidates);
    std::size_t m = 0;
    for (std::uint32_t v = 0; v < hull.vertexCount(); ++v) {
        const float s = glm::dot(n, hull.vertices[v]) - offset;
        if (s > margin) continue;
        if (m == candidates.size()) {
            // Many vertices on the plane (a finely tessellated face): move to the heap once.
            if (heapCandidates.empty()) heapCandidates.assign(candidates.begin(), candidates.end());
            heapCandidates.resize(heapCandidates.size() * 2);
            candidates = std::span(heapCandidates);
        }
        candidates[m++] = LocalContact{hull.vertices[v] - n * (0.5f * s), -s,
                                       makeFeatureId(ContactKind::Primitive, kVertex, v)};
    }
    std::array<std::uint32_t, kMaxContactPoints> keep{};
    const std::uint32_t kept = reduceContacts(candidates.first(m), n, keep);
    for (std::uint32_t i = 0; i < kept; ++i) set.points[set.count++] = candidates[keep[i]];
    return set;
}

} // namespace rubble
