// host/geometry/half_edge.cpp: polygons to a half-edge mesh (twins linked, coplanar faces merged),
// its invariant checks, and hill-climbing support points (physics report 3.2).
#include "host/geometry/half_edge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <utility>

#include "host/core/union_find.h"

namespace rubble {
namespace {

using Polygon = std::vector<std::uint32_t>;

// Small meshes are checked and built by visiting every vertex for every face (V F steps);
// larger ones by what each face and edge can see (near-linear).
bool wholeMeshChecks(std::size_t vertices, std::size_t faces) {
    return double(vertices) * double(faces) <= double(kWholeMeshCheckLimit);
}

// Largest distance of a vertex from the vertices' centroid: the length that tolerances scale by.
float boundingRadius(const std::vector<glm::vec3>& vertices) {
    glm::dvec3 centre(0.0);
    for (const glm::vec3& v : vertices) centre += glm::dvec3(v);
    centre /= double(std::max<std::size_t>(vertices.size(), 1));
    double r = 0.0;
    for (const glm::vec3& v : vertices) r = std::max(r, glm::length(glm::dvec3(v) - centre));
    return float(r);
}

// Newell's vector of a polygon: twice its area times its unit normal, exact for planar loops and
// a least-squares normal for slightly warped ones.
glm::dvec3 newellVector(const Polygon& loop, const std::vector<glm::vec3>& vertices) {
    glm::dvec3 n(0.0);
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const glm::dvec3 p(vertices[loop[i]]);
        const glm::dvec3 q(vertices[loop[(i + 1) % loop.size()]]);
        n += glm::dvec3((p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x),
                        (p.x - q.x) * (p.y + q.y));
    }
    return n;
}

std::string edgeName(std::uint32_t u, std::uint32_t v) {
    return std::to_string(u) + "-" + std::to_string(v);
}

// The polygons as plain half-edges (twins by lookup, not yet paired by index). Fails on bad
// indices, short loops, an edge used twice in one direction, or an edge without a twin.
Result<std::vector<HalfEdge>> linkPolygons(const ConvexPolygons& p, const std::string& where) {
    std::vector<HalfEdge> edges;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> byEnds;
    for (std::uint32_t f = 0; f < p.faces.size(); ++f) {
        const Polygon& loop = p.faces[f];
        if (loop.size() < 3)
            return makeError(ErrorKind::BadInput, where,
                             "face " + std::to_string(f) + " has fewer than 3 vertices");
        const auto base = std::uint32_t(edges.size());
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const std::uint32_t u = loop[i], v = loop[(i + 1) % loop.size()];
            if (u >= p.vertices.size() || v >= p.vertices.size())
                return makeError(ErrorKind::BadInput, where,
                                 "face " + std::to_string(f) + " refers to a missing vertex");
            if (u == v)
                return makeError(ErrorKind::BadInput, where,
                                 "face " + std::to_string(f) + " repeats vertex " +
                                     std::to_string(u));
            const auto h = std::uint32_t(edges.size());
            if (!byEnds.try_emplace({u, v}, h).second)
                return makeError(ErrorKind::BadInput, where,
                                 "edge " + edgeName(u, v) +
                                     " is used twice in the same direction (faces wound "
                                     "inconsistently, or more than two faces share it)");
            edges.push_back(HalfEdge{u, f, base + std::uint32_t((i + 1) % loop.size()), 0});
        }
    }
    for (HalfEdge& e : edges) {
        const std::uint32_t v = edges[e.next].origin;
        const auto twin = byEnds.find({v, e.origin});
        if (twin == byEnds.end())
            return makeError(ErrorKind::BadInput, where,
                             "the surface is open: edge " + edgeName(e.origin, v) +
                                 " belongs to one face only");
        e.twin = twin->second;
    }
    return edges;
}

// A bound on where a group of faces' vertices lie, kept for groups too large to visit whole:
// along a unit normal they lie between lo and hi, and all of them within a ball.
struct SlabBound {
    glm::dvec3 normal{0.0};
    double lo = 0.0, hi = 0.0;
    glm::dvec3 centre{0.0};
    double radius = 0.0;

    // The range of the vertices along another unit direction n: dot(n, v) = dot(normal, v) +
    // dot(n - normal, centre) + dot(n - normal, v - centre), the last term at most
    // |n - normal| radius.
    std::pair<double, double> along(const glm::dvec3& n) const {
        const glm::dvec3 tilt = n - normal;
        const double shift = glm::dot(tilt, centre), spread = glm::length(tilt) * radius;
        return {lo + shift - spread, hi + shift + spread};
    }
};

// The exact bound of a list of vertices along a unit normal.
SlabBound exactBound(const Polygon& vertices, const std::vector<glm::vec3>& points,
                     const glm::dvec3& normal) {
    SlabBound b;
    b.normal = normal;
    b.lo = std::numeric_limits<double>::max();
    b.hi = -b.lo;
    for (std::uint32_t v : vertices) {
        const glm::dvec3 p(points[v]);
        const double d = glm::dot(normal, p);
        b.lo = std::min(b.lo, d);
        b.hi = std::max(b.hi, d);
        b.centre += p;
    }
    b.centre /= double(std::max<std::size_t>(vertices.size(), 1));
    for (std::uint32_t v : vertices)
        b.radius = std::max(b.radius, glm::length(glm::dvec3(points[v]) - b.centre));
    return b;
}

// The bound of two groups' union along the unit normal n: the slab of both ranges along n,
// the ball holding both balls.
SlabBound unionBound(const SlabBound& a, const SlabBound& b, const glm::dvec3& n) {
    SlabBound u;
    u.normal = n;
    const auto [aLo, aHi] = a.along(n);
    const auto [bLo, bHi] = b.along(n);
    u.lo = std::min(aLo, bLo);
    u.hi = std::max(aHi, bHi);
    const double d = glm::length(b.centre - a.centre);
    if (d + b.radius <= a.radius) {
        u.centre = a.centre;
        u.radius = a.radius;
    } else if (d + a.radius <= b.radius) {
        u.centre = b.centre;
        u.radius = b.radius;
    } else {
        u.radius = 0.5 * (d + a.radius + b.radius);
        u.centre = a.centre + (b.centre - a.centre) * ((u.radius - a.radius) / d);
    }
    return u;
}

// Faces grouped where neighbours are coplanar, each group's boundary as one polygon. Returns
// std::nullopt when a group's boundary is not a single loop (the caller keeps the faces as they
// are). Near-linear in the half-edges: a merge visits the vertices of both groups only while
// they hold at most kExactMergeVertices together, and otherwise tests their slab bounds, which
// over-estimate the thickness (so a merge taken is always within kMergeDistance).
std::optional<ConvexPolygons> mergeCoplanarFaces(const ConvexPolygons& p,
                                                 const std::vector<HalfEdge>& edges, float scale) {
    const std::size_t faceCount = p.faces.size();
    UnionFind faces(faceCount); // smallest index as the root: the result does not depend on order
    std::vector<glm::dvec3> newell(faceCount);
    std::vector<Polygon> members(faceCount); // vertices of each small group, at its root
    std::vector<std::size_t> memberCount(faceCount);
    std::vector<SlabBound> bound(faceCount);
    for (std::uint32_t f = 0; f < faceCount; ++f) {
        newell[f] = newellVector(p.faces[f], p.vertices);
        members[f] = p.faces[f];
        memberCount[f] = members[f].size();
    }
    auto boundOf = [&](std::uint32_t f) -> SlabBound {
        return members[f].empty() ? bound[f]
                                  : exactBound(members[f], p.vertices, glm::normalize(newell[f]));
    };
    const double cosMerge = std::cos(double(kMergeAngle));
    const double thicknessLimit = double(kMergeDistance) * double(scale);
    for (std::uint32_t h = 0; h < edges.size(); ++h) {
        if (edges[h].twin < h) continue;
        std::uint32_t f = faces.find(edges[h].face);
        std::uint32_t g = faces.find(edges[edges[h].twin].face);
        if (f == g) continue;
        const glm::dvec3 nf = glm::normalize(newell[f]), ng = glm::normalize(newell[g]);
        if (glm::dot(nf, ng) < cosMerge) continue;
        // Thickness of the union along its area-weighted normal.
        const glm::dvec3 n = glm::normalize(newell[f] + newell[g]);
        const std::size_t together = memberCount[f] + memberCount[g];
        const bool exact = together <= kExactMergeVertices;
        SlabBound merged;
        if (exact) {
            double lo = std::numeric_limits<double>::max(), hi = -lo;
            for (const Polygon* group : {&members[f], &members[g]})
                for (std::uint32_t v : *group) {
                    const double d = glm::dot(n, glm::dvec3(p.vertices[v]));
                    lo = std::min(lo, d);
                    hi = std::max(hi, d);
                }
            if (hi - lo > thicknessLimit) continue;
        } else {
            merged = unionBound(boundOf(f), boundOf(g), n);
            if (merged.hi - merged.lo > thicknessLimit) continue;
        }
        if (g < f) std::swap(f, g);
        faces.unite(f, g); // f, the smaller, stays the root
        newell[f] += newell[g];
        memberCount[f] = together;
        if (exact) {
            if (members[f].size() < members[g].size()) std::swap(members[f], members[g]);
            members[f].insert(members[f].end(), members[g].begin(), members[g].end());
        } else {
            // Too large to visit again: the group keeps its bound from here on.
            bound[f] = merged;
            members[f].clear();
            members[f].shrink_to_fit();
        }
        members[g].clear();
        members[g].shrink_to_fit();
    }

    std::vector<std::uint32_t> group(faceCount);
    for (std::uint32_t f = 0; f < faceCount; ++f) group[f] = faces.find(f);
    auto interior = [&](std::uint32_t h) {
        return group[edges[h].face] == group[edges[edges[h].twin].face];
    };
    // The boundary half-edges of each group, in index order, by a counting sort on the group.
    std::vector<std::uint32_t> boundaryStart(faceCount + 1, 0);
    for (std::uint32_t h = 0; h < edges.size(); ++h)
        if (!interior(h)) ++boundaryStart[group[edges[h].face] + 1];
    for (std::size_t f = 0; f < faceCount; ++f) boundaryStart[f + 1] += boundaryStart[f];
    std::vector<std::uint32_t> boundaryEdges(boundaryStart[faceCount]);
    std::vector<std::uint32_t> cursor(boundaryStart.begin(), boundaryStart.end() - 1);
    for (std::uint32_t h = 0; h < edges.size(); ++h)
        if (!interior(h)) boundaryEdges[cursor[group[edges[h].face]]++] = h;

    ConvexPolygons out;
    out.vertices = p.vertices;
    for (std::uint32_t root = 0; root < faceCount; ++root) {
        if (group[root] != root) continue;
        const std::uint32_t boundary = boundaryStart[root + 1] - boundaryStart[root];
        if (boundary < 3) return std::nullopt;
        const std::uint32_t start = boundaryEdges[boundaryStart[root]];
        // Walk the boundary: after a boundary half-edge, turn about its end vertex across
        // interior edges until the next boundary half-edge.
        Polygon loop;
        std::uint32_t h = start;
        do {
            loop.push_back(edges[h].origin);
            std::uint32_t n = edges[h].next;
            for (std::size_t guard = 0; interior(n); ++guard) {
                if (guard > edges.size()) return std::nullopt;
                n = edges[edges[n].twin].next;
            }
            h = n;
            if (loop.size() > boundary) return std::nullopt;
        } while (h != start);
        if (loop.size() != boundary) return std::nullopt;
        out.faces.push_back(std::move(loop));
    }
    return out;
}

// Drops vertices that only two faces share (they sit between two collinear edges once their
// faces are merged); false when a face would be left with fewer than 3 vertices.
bool dropDegreeTwoVertices(ConvexPolygons& p) {
    std::vector<std::uint32_t> faceCount(p.vertices.size(), 0);
    for (const Polygon& loop : p.faces)
        for (std::uint32_t v : loop) ++faceCount[v];
    for (Polygon& loop : p.faces) {
        std::erase_if(loop, [&](std::uint32_t v) { return faceCount[v] == 2; });
        if (loop.size() < 3) return false;
    }
    return true;
}

// Removes vertices no face uses; the others keep their order.
void compactVertices(ConvexPolygons& p) {
    std::vector<std::uint32_t> remap(p.vertices.size(), std::numeric_limits<std::uint32_t>::max());
    for (const Polygon& loop : p.faces)
        for (std::uint32_t v : loop) remap[v] = 0;
    std::vector<glm::vec3> kept;
    for (std::size_t v = 0; v < p.vertices.size(); ++v) {
        if (remap[v] != 0) continue;
        remap[v] = std::uint32_t(kept.size());
        kept.push_back(p.vertices[v]);
    }
    for (Polygon& loop : p.faces)
        for (std::uint32_t& v : loop) v = remap[v];
    p.vertices = std::move(kept);
}

// The faces in breadth-first order over shared edges from face 0, so that consecutive faces
// are mostly neighbours: the face query starts each hill climb at the last face's support.
void orderFacesByAdjacency(ConvexPolygons& p) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> faceOf;
    for (std::uint32_t f = 0; f < p.faces.size(); ++f)
        for (std::size_t i = 0; i < p.faces[f].size(); ++i)
            faceOf[{p.faces[f][i], p.faces[f][(i + 1) % p.faces[f].size()]}] = f;
    std::vector<std::uint32_t> order;
    std::vector<std::uint8_t> seen(p.faces.size(), 0);
    for (std::uint32_t root = 0; root < p.faces.size(); ++root) {
        if (seen[root]) continue;
        seen[root] = 1;
        order.push_back(root);
        for (std::size_t head = order.size() - 1; head < order.size(); ++head) {
            const Polygon& loop = p.faces[order[head]];
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const auto it = faceOf.find({loop[(i + 1) % loop.size()], loop[i]});
                if (it == faceOf.end() || seen[it->second]) continue;
                seen[it->second] = 1;
                order.push_back(it->second);
            }
        }
    }
    std::vector<Polygon> faces;
    faces.reserve(order.size());
    for (std::uint32_t f : order) faces.push_back(std::move(p.faces[f]));
    p.faces = std::move(faces);
}

// The final mesh: twins at 2k and 2k+1, planes, one edge per vertex, edge records, bounds.
// Fails when an edge lacks one of its directions.
Result<HalfEdgeMesh> assemble(const ConvexPolygons& p, const std::string& where) {
    HalfEdgeMesh m;
    m.vertices = p.vertices;
    constexpr std::uint32_t kUnset = std::numeric_limits<std::uint32_t>::max();
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edgeOf;
    for (std::uint32_t f = 0; f < p.faces.size(); ++f) {
        const Polygon& loop = p.faces[f];
        Polygon halves(loop.size());
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const std::uint32_t u = loop[i], v = loop[(i + 1) % loop.size()];
            const auto [it, added] =
                edgeOf.try_emplace({std::min(u, v), std::max(u, v)}, m.edgeCount());
            if (added) m.edges.resize(m.edges.size() + 2, HalfEdge{kUnset, kUnset, kUnset, kUnset});
            const std::uint32_t h = 2 * it->second + (added ? 0 : 1);
            if (m.edges[h].face != kUnset)
                return makeError(ErrorKind::BadInput, where,
                                 "edge " + edgeName(u, v) + " is shared by more than two faces");
            m.edges[h].origin = u;
            m.edges[h].face = f;
            m.edges[h].twin = h ^ 1u;
            halves[i] = h;
        }
        for (std::size_t i = 0; i < loop.size(); ++i)
            m.edges[halves[i]].next = halves[(i + 1) % loop.size()];
        HalfEdgeFace face;
        face.normal = glm::vec3(glm::normalize(newellVector(loop, p.vertices)));
        face.edge = halves[0];
        m.faces.push_back(face);
    }
    for (std::uint32_t h = 0; h < m.edges.size(); ++h)
        if (m.edges[h].face == kUnset) {
            const HalfEdge& t = m.edges[h ^ 1u];
            return makeError(ErrorKind::BadInput, where,
                             "the surface is open: edge " +
                                 edgeName(t.origin, m.edges[t.next].origin) +
                                 " belongs to one face only");
        }
    m.vertexEdge.assign(m.vertices.size(), kUnset);
    for (std::uint32_t h = 0; h < m.edges.size(); ++h)
        if (m.vertexEdge[m.edges[h].origin] == kUnset) m.vertexEdge[m.edges[h].origin] = h;
    m.neighbourStart.assign(1, 0);
    for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
        std::uint32_t h = m.vertexEdge[v];
        std::size_t guard = 0;
        do {
            const HalfEdge& twin = m.edges[m.edges[h].twin];
            m.neighbours.push_back(twin.origin);
            h = twin.next;
        } while (h != m.vertexEdge[v] && ++guard < m.edges.size());
        m.neighbourStart.push_back(std::uint32_t(m.neighbours.size()));
    }
    // Each plane passes through the hull's support point along its normal: every vertex tried
    // on a small mesh, hill climbing from the face's own corner on a large one (exact on a
    // convex mesh, and the corner is already the support up to rounding).
    const bool visitAll = wholeMeshChecks(m.vertices.size(), m.faces.size());
    for (HalfEdgeFace& face : m.faces) {
        float best = -std::numeric_limits<float>::max();
        if (visitAll) {
            for (const glm::vec3& v : m.vertices) best = std::max(best, glm::dot(face.normal, v));
        } else {
            const std::uint32_t corner = m.edges[face.edge].origin;
            best = glm::dot(face.normal, m.vertices[supportVertex(m, face.normal, corner)]);
        }
        face.offset = best;
    }
    m.edgeRecords.resize(m.edgeCount());
    for (std::uint32_t k = 0; k < m.edgeCount(); ++k) {
        const HalfEdge& left = m.edges[2 * k];
        const HalfEdge& right = m.edges[2 * k + 1];
        HalfEdgeEdge& r = m.edgeRecords[k];
        r.origin = m.vertices[left.origin];
        r.direction = m.vertices[right.origin] - r.origin;
        r.normalLeft = m.faces[left.face].normal;
        r.normalRight = m.faces[right.face].normal;
        r.arc = glm::cross(r.normalRight, r.normalLeft);
    }
    const std::size_t e = m.edgeCount();
    m.edgeArcs.resize(9 * e);
    for (std::size_t k = 0; k < e; ++k) {
        const HalfEdgeEdge& r = m.edgeRecords[k];
        for (int c = 0; c < 3; ++c) {
            m.edgeArcs[std::size_t(c) * e + k] = r.arc[c];
            m.edgeArcs[std::size_t(3 + c) * e + k] = r.normalLeft[c];
            m.edgeArcs[std::size_t(6 + c) * e + k] = r.normalRight[c];
        }
    }
    if (!m.vertices.empty()) {
        glm::dvec3 sum(0.0);
        for (const glm::vec3& v : m.vertices) sum += glm::dvec3(v);
        m.centroid = glm::vec3(sum / double(m.vertices.size()));
        m.boundsMin = m.boundsMax = m.vertices[0];
        for (const glm::vec3& v : m.vertices) {
            m.boundsMin = glm::min(m.boundsMin, v);
            m.boundsMax = glm::max(m.boundsMax, v);
        }
    }
    return m;
}

Error invariant(const std::string& where, const std::string& what) {
    return makeError(ErrorKind::BadInput, where, "broken convex mesh: " + what);
}

} // namespace

Result<HalfEdgeMesh> buildHalfEdgeMesh(const ConvexPolygons& polygons, const std::string& where) {
    if (polygons.vertices.size() < 4 || polygons.faces.size() < 4)
        return invariant(where, "a closed polyhedron needs at least 4 vertices and 4 faces, got " +
                                    std::to_string(polygons.vertices.size()) + " and " +
                                    std::to_string(polygons.faces.size()));
    Result<std::vector<HalfEdge>> linked = linkPolygons(polygons, where);
    if (!linked) return invariant(where, linked.error().message);
    const float scale = boundingRadius(polygons.vertices);
    if (std::optional<ConvexPolygons> merged = mergeCoplanarFaces(polygons, *linked, scale)) {
        if (dropDegreeTwoVertices(*merged)) {
            compactVertices(*merged);
            orderFacesByAdjacency(*merged);
            Result<HalfEdgeMesh> mesh = assemble(*merged, where);
            if (mesh && checkHalfEdgeMesh(*mesh, where).ok()) return mesh;
        }
    }
    // Merging went wrong (a group that is not a disk): the faces as given, checked.
    ConvexPolygons plain = polygons;
    compactVertices(plain);
    orderFacesByAdjacency(plain);
    Result<HalfEdgeMesh> mesh = assemble(plain, where);
    if (!mesh) return invariant(where, mesh.error().message);
    RUBBLE_TRY(checkHalfEdgeMesh(*mesh, where));
    return mesh;
}

Status checkHalfEdgeMesh(const HalfEdgeMesh& m, const std::string& where) {
    const std::size_t vCount = m.vertices.size(), hCount = m.edges.size(), fCount = m.faces.size();
    if (hCount % 2 != 0 || m.vertexEdge.size() != vCount || m.edgeRecords.size() != hCount / 2 ||
        m.neighbourStart.size() != vCount + 1 || m.neighbours.size() != hCount ||
        m.edgeArcs.size() != 9 * (hCount / 2))
        return invariant(where, "array sizes do not match");
    for (std::uint32_t h = 0; h < hCount; ++h) {
        const HalfEdge& e = m.edges[h];
        const std::string name = "half-edge " + std::to_string(h);
        if (e.origin >= vCount || e.face >= fCount || e.next >= hCount || e.twin >= hCount)
            return invariant(where, name + " refers to a missing element");
        if (e.twin != (h ^ 1u) || m.edges[e.twin].twin != h)
            return invariant(where, name + " has no twin");
        if (m.edges[e.twin].origin != m.edges[e.next].origin)
            return invariant(where, name + " and its twin do not join the same two vertices");
        if (m.edges[e.twin].face == e.face)
            return invariant(where, name + " has its twin in the same face");
        if (m.edges[e.next].face != e.face)
            return invariant(where, name + " leaves its face through next");
    }
    for (std::uint32_t v = 0; v < vCount; ++v)
        if (m.vertexEdge[v] >= hCount || m.edges[m.vertexEdge[v]].origin != v)
            return invariant(where, "vertex " + std::to_string(v) + " has no edge leaving it");

    // Face loops close and cover every half-edge once.
    std::size_t covered = 0;
    for (std::uint32_t f = 0; f < fCount; ++f) {
        std::uint32_t h = m.faces[f].edge, length = 0;
        if (h >= hCount || m.edges[h].face != f)
            return invariant(where, "face " + std::to_string(f) + " names a foreign edge");
        do {
            h = m.edges[h].next;
            if (++length > hCount)
                return invariant(where,
                                 "the loop of face " + std::to_string(f) + " does not close");
        } while (h != m.faces[f].edge);
        if (length < 3)
            return invariant(where, "face " + std::to_string(f) + " has fewer than 3 edges");
        covered += length;
    }
    if (covered != hCount) return invariant(where, "some half-edges belong to no face loop");
    const long euler = long(vCount) - long(hCount / 2) + long(fCount);
    if (euler != 2)
        return invariant(where, "V - E + F = " + std::to_string(euler) + ", expected 2 (" +
                                    std::to_string(vCount) + " - " + std::to_string(hCount / 2) +
                                    " + " + std::to_string(fCount) + ")");

    // Geometry: supporting planes, planar and convex faces, outward normals.
    const float tol = kShapeTolerance * std::max(boundingRadius(m.vertices), 1e-6f);
    glm::dvec3 centroid(0.0);
    for (const glm::vec3& v : m.vertices) centroid += glm::dvec3(v);
    centroid /= double(vCount);
    for (std::uint32_t f = 0; f < fCount; ++f) {
        const HalfEdgeFace& face = m.faces[f];
        const std::string name = "face " + std::to_string(f);
        if (!(std::fabs(glm::length(face.normal) - 1.0f) < 1e-4f))
            return invariant(where, name + " has no unit normal (zero area)");
        // Outward: the centroid lies below the face's own vertices.
        const glm::vec3 corner = m.vertices[m.edges[face.edge].origin];
        if (!(glm::dot(glm::dvec3(face.normal), centroid - glm::dvec3(corner)) < 0.0))
            return invariant(where, name + " faces inward (wound clockwise seen from outside)");
        if (wholeMeshChecks(vCount, fCount)) {
            for (std::uint32_t v = 0; v < vCount; ++v)
                if (glm::dot(face.normal, m.vertices[v]) > face.offset + tol)
                    return invariant(where, "vertex " + std::to_string(v) +
                                                " lies above the plane of " + name +
                                                " (the mesh is not convex)");
        } else {
            // Large meshes: the support along the normal, climbed from the face, is the face
            // itself, and every neighbouring face's far corner lies below the face's own plane
            // (every edge convex); with the planar, convex faces and V - E + F = 2 checked here,
            // the surface is convex.
            const float own = glm::dot(face.normal, corner);
            const std::uint32_t top = supportVertex(m, face.normal, m.edges[face.edge].origin);
            std::uint32_t e = face.edge;
            do {
                const HalfEdge& twin = m.edges[m.edges[e].twin];
                const std::uint32_t far = m.edges[m.edges[twin.next].next].origin;
                for (const std::uint32_t v : {top, far})
                    if (glm::dot(face.normal, m.vertices[v]) > std::min(own, face.offset) + tol)
                        return invariant(where, "vertex " + std::to_string(v) +
                                                    " lies above the plane of " + name +
                                                    " (the mesh is not convex)");
                e = m.edges[e].next;
            } while (e != face.edge);
        }
        std::uint32_t h = face.edge;
        do {
            const HalfEdge& e = m.edges[h];
            const glm::vec3 a = m.vertices[e.origin];
            const glm::vec3 b = m.vertices[m.edges[e.next].origin];
            const glm::vec3 c = m.vertices[m.edges[m.edges[e.next].next].origin];
            if (glm::dot(face.normal, a) < face.offset - tol)
                return invariant(where, "vertex " + std::to_string(e.origin) +
                                            " lies below the "
                                            "plane of " +
                                            name +
                                            " (the face is not planar, or the "
                                            "mesh is not convex)");
            const float turn = glm::dot(glm::cross(b - a, c - b), face.normal);
            if (turn < -tol * (glm::length(b - a) + glm::length(c - b)))
                return invariant(where, name + " is not convex at vertex " +
                                            std::to_string(m.edges[e.next].origin));
            h = e.next;
        } while (h != face.edge);
    }
    return {};
}

std::uint32_t supportVertex(const HalfEdgeMesh& m, glm::vec3 d, std::uint32_t start) {
    const glm::vec3* vertices = m.vertices.data();
    const std::uint32_t* ring = m.neighbours.data();
    std::uint32_t best = start;
    float bestDot = glm::dot(d, vertices[best]);
    for (;;) {
        // The neighbours, in turn about the vertex (twin, then next, flattened at build).
        std::uint32_t climb = best;
        float climbDot = bestDot;
        const std::uint32_t end = m.neighbourStart[best + 1];
        for (std::uint32_t i = m.neighbourStart[best]; i < end; ++i) {
            const float dot = glm::dot(d, vertices[ring[i]]);
            if (dot > climbDot) {
                climbDot = dot;
                climb = ring[i];
            }
        }
        if (climb == best) return best;
        best = climb;
        bestDot = climbDot;
    }
}

std::uint32_t supportVertexBruteForce(const HalfEdgeMesh& m, glm::vec3 d) {
    std::uint32_t best = 0;
    float bestDot = glm::dot(d, m.vertices[0]);
    for (std::uint32_t v = 1; v < m.vertexCount(); ++v) {
        const float dot = glm::dot(d, m.vertices[v]);
        if (dot > bestDot) {
            bestDot = dot;
            best = v;
        }
    }
    return best;
}

std::vector<std::uint32_t> faceVertices(const HalfEdgeMesh& m, std::uint32_t face) {
    std::vector<std::uint32_t> loop;
    std::uint32_t h = m.faces[face].edge;
    do {
        loop.push_back(m.edges[h].origin);
        h = m.edges[h].next;
    } while (h != m.faces[face].edge);
    return loop;
}

} // namespace rubble
