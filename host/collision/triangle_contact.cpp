// host/collision/triangle_contact.cpp: contacts of a static triangle with spheres, capsules and
// convex hulls (stage narrowPhase, CPU); see triangle_contact.h.
#include "host/collision/triangle_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rubble/shared/clip.h"

namespace rubble {
namespace {

// A normal this close to the face's (cosine) is the face's.
constexpr float kFaceCosine = 1.0f - 1e-5f;
// Slack of the arc test of a convex edge (cosine).
constexpr float kArcSlack = 1e-4f;
// Vertices this close to the furthest along a normal (fraction of the longest edge) share it.
constexpr float kFeatureTolerance = 1e-4f;
// A hull face must separate by this much more than the triangle's face to be chosen, and an
// edge pair by kEdgeBias more (m): faces give the steadier manifolds.
constexpr float kFaceBias = 5e-4f;
constexpr float kEdgeBias = 1e-3f;
// Hulls with at most this many vertices find their support by trying every vertex, which is
// faster than hill climbing when the vertices are already placed.
constexpr std::size_t kBruteSupportVertices = 16;
// Closer than this (m) the direction between closest points is no normal.
constexpr float kTinyDistance = 1e-6f;

std::uint32_t featureOf(std::uint32_t triangle, std::uint32_t tag) {
    return shared::makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, triangle & 0x7FFFu, tag);
}

float longestEdge(const LevelTriangle& t) {
    return std::max({glm::length(t.v[1] - t.v[0]), glm::length(t.v[2] - t.v[1]),
                     glm::length(t.v[0] - t.v[2])});
}

bool edgeAllows(const LevelTriangle& t, float side, int k, glm::vec3 normal) {
    const EdgeKind kind = t.edges[std::size_t(k)];
    if (kind == EdgeKind::Boundary) return true;
    if (kind == EdgeKind::Flat) return false;
    // A concave edge seen from the back is convex.
    const bool convex = (kind == EdgeKind::Convex) == (side > 0.0f);
    if (!convex) return false;
    const glm::vec3 face = side * t.normal;
    const glm::vec3 other = side * t.neighbourNormal[std::size_t(k)];
    const glm::vec3 e = glm::normalize(t.v[std::size_t((k + 1) % 3)] - t.v[std::size_t(k)]);
    glm::vec3 across = normal - e * glm::dot(normal, e);
    const float len = glm::length(across);
    if (len < kTinyDistance) return false;
    across /= len;
    const float c = glm::dot(face, other);
    return glm::dot(across, face) >= c - kArcSlack && glm::dot(across, other) >= c - kArcSlack;
}

// The point of the segment between the ends a and b, in the mesh frame, midway between the
// surfaces of a body whose surface point is `onBody` and a triangle at `separation` from it.
void addContact(std::vector<TriangleContact>& out, glm::vec3 onBody, glm::vec3 normal,
                float separation, std::uint32_t feature) {
    out.push_back({onBody - normal * (0.5f * separation), -separation, normal, feature});
}

// Sutherland-Hodgman: the part of `in` where dot(n, x - origin) <= 0. A new corner is tagged
// 0x800 | plane << 8 | the low byte of the tag of the edge's start.
void clipPolygon(const std::vector<TaggedPoint>& in, glm::vec3 n, glm::vec3 origin,
                 std::uint32_t plane, std::vector<TaggedPoint>& out) {
    out.clear();
    for (std::size_t i = 0; i < in.size(); ++i) {
        const TaggedPoint a = in[i], b = in[(i + 1) % in.size()];
        const float da = glm::dot(n, a.position - origin), db = glm::dot(n, b.position - origin);
        if (da <= 0.0f) out.push_back(a);
        if ((da < 0.0f && db > 0.0f) || (da > 0.0f && db < 0.0f))
            out.push_back({a.position + (b.position - a.position) * (da / (da - db)),
                           0x800u | ((plane & 0x7u) << 8) | (a.tag & 0xFFu)});
    }
}

// Outward normal of the triangle's side through edge k (not unit).
glm::vec3 sideNormal(const LevelTriangle& t, int k) {
    return glm::cross(t.v[std::size_t((k + 1) % 3)] - t.v[std::size_t(k)], t.normal);
}

// The segment clipped to the prism over the triangle; false when nothing is left.
bool clipSegmentToPrism(const LevelTriangle& t, Segment& s) {
    for (int k = 0; k < 3; ++k) {
        const glm::vec3 n = sideNormal(t, k);
        const float d0 = glm::dot(n, s.p0 - t.v[std::size_t(k)]);
        const float d1 = glm::dot(n, s.p1 - t.v[std::size_t(k)]);
        if (d0 > 0.0f && d1 > 0.0f) return false;
        if (d0 > 0.0f) s.p0 = s.p0 + (s.p1 - s.p0) * (d0 / (d0 - d1));
        if (d1 > 0.0f) s.p1 = s.p1 + (s.p0 - s.p1) * (d1 / (d1 - d0));
    }
    return true;
}

} // namespace

void placeHull(const HalfEdgeMesh& hull, const glm::mat3& rotation, glm::vec3 translation,
               PlacedHull& out) {
    out.mesh = &hull;
    out.rotation = rotation;
    out.translation = translation;
    out.vertices.resize(hull.vertices.size());
    for (std::size_t i = 0; i < hull.vertices.size(); ++i)
        out.vertices[i] = rotation * hull.vertices[i] + translation;
    out.faceNormals.resize(hull.faces.size());
    out.faceOffsets.resize(hull.faces.size());
    for (std::size_t f = 0; f < hull.faces.size(); ++f) {
        out.faceNormals[f] = rotation * hull.faces[f].normal;
        const glm::vec3 corner = out.vertices[hull.edges[hull.faces[f].edge].origin];
        out.faceOffsets[f] = glm::dot(out.faceNormals[f], corner);
    }
    out.edgeOrigins.resize(hull.edgeRecords.size());
    out.edgeDirections.resize(hull.edgeRecords.size());
    for (std::size_t e = 0; e < hull.edgeRecords.size(); ++e) {
        out.edgeOrigins[e] = rotation * hull.edgeRecords[e].origin + translation;
        out.edgeDirections[e] = rotation * hull.edgeRecords[e].direction;
    }
    out.centroid = rotation * hull.centroid + translation;
}

bool normalAllowed(const LevelTriangle& t, float side, glm::vec3 normal) {
    const glm::vec3 face = side * t.normal;
    if (glm::dot(normal, face) >= kFaceCosine) return true;
    float d[3], top = -std::numeric_limits<float>::max();
    for (int k = 0; k < 3; ++k) top = std::max(top, d[k] = glm::dot(normal, t.v[std::size_t(k)]));
    const float tolerance = kFeatureTolerance * longestEdge(t);
    bool at[3];
    int count = 0;
    for (int k = 0; k < 3; ++k) count += (at[k] = d[k] >= top - tolerance) ? 1 : 0;
    if (count == 3) return glm::dot(normal, face) > 0.0f;
    if (count == 2) {
        const int k = !at[0] ? 1 : !at[1] ? 2 : 0; // the edge from v[k] to v[k + 1]
        return edgeAllows(t, side, k, normal);
    }
    const int i = at[0] ? 0 : at[1] ? 1 : 2;
    return edgeAllows(t, side, i, normal) || edgeAllows(t, side, (i + 2) % 3, normal);
}

glm::vec3 closestOnTriangle(const LevelTriangle& t, glm::vec3 p, int& feature) {
    const glm::vec3 a = t.v[0], b = t.v[1], c = t.v[2];
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return feature = 0, a;
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) return feature = 1, b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return feature = 3, a + ab * (d1 / (d1 - d3));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) return feature = 2, c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return feature = 5, a + ac * (d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
        return feature = 4, b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const float denom = 1.0f / (va + vb + vc);
    feature = 6;
    return a + ab * (vb * denom) + ac * (vc * denom);
}

void collideTriangleSphere(const LevelTriangle& t, std::uint32_t index, glm::vec3 c, float r,
                           float margin, std::vector<TriangleContact>& out) {
    int feature = 0;
    const glm::vec3 q = closestOnTriangle(t, c, feature);
    const float distance = glm::length(c - q);
    if (distance > r + margin) return;
    const float above = glm::dot(t.normal, c - t.v[0]);
    const float side = above >= 0.0f ? 1.0f : -1.0f;
    const glm::vec3 face = side * t.normal;
    glm::vec3 n = feature == 6 || distance < kTinyDistance ? face : (c - q) / distance;
    // Past an internal edge the neighbour's face is the surface: this one's plane continues.
    if (!normalAllowed(t, side, n)) n = face;
    const bool onFace = glm::dot(n, face) >= kFaceCosine;
    const float separation = (onFace ? side * above : distance) - r;
    if (separation > margin) return;
    addContact(out, c - n * r, n, separation, featureOf(index, 0));
}

void collideTriangleCapsule(const LevelTriangle& t, std::uint32_t index, const Segment& s,
                            float r, float margin, std::vector<TriangleContact>& out) {
    // The closest points of segment and triangle: where the segment pierces it, its ends
    // against the triangle, or its closest points to the triangle's edges.
    glm::vec3 onSegment = s.p0, onTriangle = s.p0;
    float best = std::numeric_limits<float>::max();
    int feature = 6;
    const float s0 = glm::dot(t.normal, s.p0 - t.v[0]), s1 = glm::dot(t.normal, s.p1 - t.v[0]);
    if ((s0 <= 0.0f && s1 >= 0.0f) || (s0 >= 0.0f && s1 <= 0.0f)) {
        const glm::vec3 x = s0 == s1 ? s.p0 : s.p0 + (s.p1 - s.p0) * (s0 / (s0 - s1));
        int f = 0;
        closestOnTriangle(t, x, f);
        if (f == 6) onSegment = onTriangle = x, best = 0.0f, feature = 6;
    }
    for (const glm::vec3 end : {s.p0, s.p1}) {
        int f = 0;
        const glm::vec3 q = closestOnTriangle(t, end, f);
        const float d = glm::length(end - q);
        if (d < best) onSegment = end, onTriangle = q, best = d, feature = f;
    }
    for (int k = 0; k < 3; ++k) {
        const SegmentClosest c = closestSegmentPoints(
            s, Segment{t.v[std::size_t(k)], t.v[std::size_t((k + 1) % 3)]});
        const float d = glm::length(c.onA - c.onB);
        if (d < best) onSegment = c.onA, onTriangle = c.onB, best = d, feature = 3 + k;
    }
    if (best > r + margin) return;
    const glm::vec3 mid = 0.5f * (s.p0 + s.p1);
    const float reference = glm::dot(t.normal, onSegment - t.v[0]);
    const float side =
        (std::abs(reference) > kTinyDistance ? reference : glm::dot(t.normal, mid - t.v[0])) >= 0.0f
            ? 1.0f
            : -1.0f;
    const glm::vec3 face = side * t.normal;
    glm::vec3 n = feature == 6 || best < kTinyDistance ? face : (onSegment - onTriangle) / best;
    if (!normalAllowed(t, side, n)) n = face;
    if (glm::dot(n, face) < kFaceCosine) {
        addContact(out, onSegment - n * r, n, best - r, featureOf(index, 0));
        return;
    }
    // Lying on the face: the ends of the segment over the triangle.
    const std::size_t before = out.size();
    Segment over = s;
    if (clipSegmentToPrism(t, over)) {
        const glm::vec3 ends[2] = {over.p0, over.p1};
        const int count = glm::length(over.p1 - over.p0) > kTinyDistance ? 2 : 1;
        for (int k = 0; k < count; ++k) {
            const float separation = glm::dot(face, ends[k] - t.v[0]) - r;
            if (separation <= margin)
                addContact(out, ends[k] - face * r, face, separation,
                           featureOf(index, 1 + std::uint32_t(k)));
        }
    }
    if (out.size() > before) return;
    const float separation = glm::dot(face, onSegment - t.v[0]) - r;
    if (separation <= margin) addContact(out, onSegment - face * r, face, separation, featureOf(index, 0));
}

void collideTriangleHull(const LevelTriangle& t, std::uint32_t index, PlacedHull& hull,
                         float margin, std::vector<TriangleContact>& out) {
    const HalfEdgeMesh& mesh = *hull.mesh;
    const glm::mat3 toHull = glm::transpose(hull.rotation);
    // Least of dot(u, x) over the hull: over the placed vertices when they are few (a box, a
    // rock), by hill climbing in the hull's own frame otherwise.
    const bool fewVertices = hull.vertices.size() <= kBruteSupportVertices;
    const auto hullMin = [&](glm::vec3 u) {
        if (fewVertices) {
            float low = glm::dot(u, hull.vertices[0]);
            for (std::size_t v = 1; v < hull.vertices.size(); ++v)
                low = std::min(low, glm::dot(u, hull.vertices[v]));
            return low;
        }
        const std::uint32_t v = supportVertex(mesh, toHull * -u);
        return glm::dot(u, hull.vertices[v]);
    };
    const auto triangleMax = [&](glm::vec3 u) {
        return std::max({glm::dot(u, t.v[0]), glm::dot(u, t.v[1]), glm::dot(u, t.v[2])});
    };
    const float side = glm::dot(t.normal, hull.centroid - t.v[0]) >= 0.0f ? 1.0f : -1.0f;
    const glm::vec3 face = side * t.normal;

    // The triangle's face.
    enum class Axis { Triangle, HullFace, Edges } axis = Axis::Triangle;
    float best = hullMin(face) - glm::dot(face, t.v[0]);
    if (best > margin) return;
    glm::vec3 normal = face;
    std::size_t chosenFace = 0, chosenEdge = 0;
    int chosenSide = 0;
    // The hull's faces: u = -n_f, separation = min over the corners of n_f . v - offset.
    for (std::size_t f = 0; f < hull.faceNormals.size(); ++f) {
        const glm::vec3 n = hull.faceNormals[f];
        const float separation = std::min({glm::dot(n, t.v[0]), glm::dot(n, t.v[1]),
                                           glm::dot(n, t.v[2])}) -
                                 hull.faceOffsets[f];
        if (separation > margin) return;
        if (separation > best + kFaceBias && normalAllowed(t, side, -n)) {
            best = separation, normal = -n, axis = Axis::HullFace, chosenFace = f;
        }
    }
    // Edge pairs, each axis turned from the triangle towards the hull, for the triangle's edges
    // that can carry a normal of their own: boundaries and edges convex from this side.
    bool edgeMayTouch[3];
    for (std::size_t k = 0; k < 3; ++k)
        edgeMayTouch[k] = t.edges[k] == EdgeKind::Boundary ||
                          (t.edges[k] == EdgeKind::Convex && side > 0.0f) ||
                          (t.edges[k] == EdgeKind::Concave && side < 0.0f);
    const glm::vec3 centre = (t.v[0] + t.v[1] + t.v[2]) / 3.0f;
    const float tolerance = kFeatureTolerance * longestEdge(t);
    // The triangle's edges, once for all the hull's edges.
    glm::vec3 edgeStart[3], edgeEnd[3], edgeVector[3];
    float edgeLength[3];
    for (std::size_t k = 0; k < 3; ++k) {
        edgeStart[k] = t.v[k];
        edgeEnd[k] = t.v[(k + 1) % 3];
        edgeVector[k] = edgeEnd[k] - edgeStart[k];
        edgeLength[k] = glm::length(edgeVector[k]);
    }
    for (std::size_t e = 0; e < hull.edgeDirections.size(); ++e) {
        const glm::vec3 dh = hull.edgeDirections[e];
        const float hullEdgeLength = glm::length(dh);
        for (int k = 0; k < 3; ++k) {
            // An internal edge never gives the normal; past it the neighbour's face (or, here,
            // this face clipped to the prism) holds whatever touches.
            if (!edgeMayTouch[k]) continue;
            const glm::vec3 a0 = edgeStart[k], a1 = edgeEnd[k];
            glm::vec3 u = glm::cross(dh, edgeVector[k]);
            const float len = glm::length(u);
            if (len <= 1e-5f * hullEdgeLength * edgeLength[k]) continue;
            u /= len;
            if (glm::dot(u, hull.centroid - centre) < 0.0f) u = -u;
            // The gap between the two edges' lines along u bounds the separation from above
            // (the hull's least and the triangle's most include the edges' own points): when it
            // can neither separate nor win, the support queries are skipped.
            const float gap = glm::dot(u, hull.edgeOrigins[e]) - glm::dot(u, a0);
            if (gap <= std::min(margin, best + kEdgeBias)) continue;
            const float low = hullMin(u), high = triangleMax(u);
            const float separation = low - high;
            if (separation > margin) return;
            if (separation <= best + kEdgeBias) continue;
            // A true edge contact: both edges lie on their shapes' extremes along the axis.
            const float originDepth = glm::dot(u, hull.edgeOrigins[e]);
            const float endDepth = glm::dot(u, hull.edgeOrigins[e] + dh);
            if (originDepth > low + tolerance || endDepth > low + tolerance) continue;
            if (glm::dot(u, a0) < high - tolerance || glm::dot(u, a1) < high - tolerance) continue;
            if (!normalAllowed(t, side, u)) continue;
            best = separation, normal = u, axis = Axis::Edges, chosenEdge = e, chosenSide = k;
        }
    }

    if (axis == Axis::Edges) {
        const glm::vec3 a0 = t.v[std::size_t(chosenSide)];
        const glm::vec3 a1 = t.v[std::size_t((chosenSide + 1) % 3)];
        const SegmentClosest c = closestSegmentPoints(
            Segment{hull.edgeOrigins[chosenEdge],
                    hull.edgeOrigins[chosenEdge] + hull.edgeDirections[chosenEdge]},
            Segment{a0, a1});
        addContact(out, c.onA, normal, best,
                   featureOf(index, 0x4000u | (std::uint32_t(chosenEdge) << 2) |
                                        std::uint32_t(chosenSide)));
        return;
    }
    if (axis == Axis::HullFace) {
        // The triangle clipped to the hull's face; its points below the face touch.
        const glm::vec3 n = hull.faceNormals[chosenFace];
        hull.polygon = {{t.v[0], 0u}, {t.v[1], 1u}, {t.v[2], 2u}};
        const std::uint32_t start = mesh.faces[chosenFace].edge;
        std::uint32_t h = start;
        do {
            const glm::vec3 w0 = hull.vertices[mesh.edges[h].origin];
            const glm::vec3 w1 = hull.vertices[mesh.edges[mesh.edges[h].next].origin];
            clipPolygon(hull.polygon, glm::cross(w1 - w0, n), w0, h, hull.clipped);
            std::swap(hull.polygon, hull.clipped);
            h = mesh.edges[h].next;
        } while (h != start && !hull.polygon.empty());
        for (const TaggedPoint& corner : hull.polygon) {
            const glm::vec3 q = corner.position;
            const float separation = glm::dot(n, q) - hull.faceOffsets[chosenFace];
            if (separation <= margin)
                addContact(out, q - n * separation, normal, separation,
                           featureOf(index, 0x2000u | (corner.tag & 0xFFFu)));
        }
        return;
    }
    // The hull's face most against the triangle's normal, clipped to the triangle's prism.
    std::size_t incident = 0;
    for (std::size_t f = 1; f < hull.faceNormals.size(); ++f)
        if (glm::dot(hull.faceNormals[f], face) < glm::dot(hull.faceNormals[incident], face))
            incident = f;
    hull.polygon.clear();
    const std::uint32_t start = mesh.faces[incident].edge;
    std::uint32_t h = start;
    do {
        hull.polygon.push_back({hull.vertices[mesh.edges[h].origin], mesh.edges[h].origin & 0x7FFu});
        h = mesh.edges[h].next;
    } while (h != start);
    for (int k = 0; k < 3 && !hull.polygon.empty(); ++k) {
        clipPolygon(hull.polygon, sideNormal(t, k), t.v[std::size_t(k)], std::uint32_t(k),
                    hull.clipped);
        std::swap(hull.polygon, hull.clipped);
    }
    for (const TaggedPoint& corner : hull.polygon) {
        const float separation = glm::dot(face, corner.position - t.v[0]);
        if (separation <= margin)
            addContact(out, corner.position, face, separation,
                       featureOf(index, 0x1000u | (corner.tag & 0xFFFu)));
    }
}

} // namespace rubble
