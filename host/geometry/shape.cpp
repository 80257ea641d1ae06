// host/geometry/shape.cpp: ShapeDesc to Shape: hulls, mass properties, centre-of-mass shift.
#include "host/geometry/shape.h"

#include <algorithm>
#include <map>
#include <tuple>

namespace rubble {

ConvexPolygons boxPolygons(glm::vec3 h) {
    ConvexPolygons p;
    // Corner i has x = +h.x when bit 0 is set, y when bit 1, z when bit 2.
    for (int i = 0; i < 8; ++i)
        p.vertices.emplace_back(i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z);
    p.faces = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3}, {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
    return p;
}

bool isClosedMesh(const TriangleMesh& mesh) {
    // Weld vertices by position, then count directed edges.
    std::map<std::tuple<float, float, float>, std::uint32_t> weld;
    std::vector<std::uint32_t> id(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const glm::vec3& v = mesh.vertices[i];
        id[i] = weld.try_emplace({v.x, v.y, v.z}, std::uint32_t(weld.size())).first->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const glm::uvec3& t : mesh.triangles) {
        const std::uint32_t a = id[t.x], b = id[t.y], c = id[t.z];
        if (a == b || b == c || c == a) return false;
        for (auto e : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            if (++directed[e] > 1) return false;
    }
    for (const auto& [e, n] : directed)
        if (!directed.count({e.second, e.first})) return false;
    return true;
}

namespace {

float boundingRadiusOf(const std::vector<glm::vec3>& vertices) {
    float r = 0.0f;
    for (const glm::vec3& v : vertices) r = std::max(r, glm::length(v));
    return r;
}

} // namespace

namespace {

// The static mesh's triangles, in the shape frame (the file's less the centre shift).
Status attachLevel(Shape& s, const ShapeDesc& d) {
    TriangleMesh mesh{d.points, d.triangles};
    for (glm::vec3& v : mesh.vertices) v -= s.centreShift;
    Result<LevelMesh> level = buildLevelMesh(mesh, d.where + (d.heightField ? ".heights" : ".file"));
    RUBBLE_TRY(level);
    s.mesh = std::move(mesh);
    s.boundingRadius = std::max(glm::length(level->boundsMin), glm::length(level->boundsMax));
    s.level = std::make_shared<const LevelMesh>(std::move(*level));
    return {};
}

} // namespace

Result<Shape> buildShape(const ShapeDesc& d, ShapeUse use) {
    Shape s;
    s.name = d.name;
    s.type = d.type;
    switch (d.type) {
    case ShapeType::Box:
        s.halfExtents = d.halfExtents;
        s.hull = boxPolygons(d.halfExtents);
        s.unitMass = boxMassProperties(d.halfExtents);
        s.boundingRadius = glm::length(d.halfExtents);
        break;
    case ShapeType::Sphere:
        s.radius = d.radius;
        s.unitMass = sphereMassProperties(d.radius);
        s.boundingRadius = d.radius;
        return s;
    case ShapeType::Plane:
        s.normal = d.normal;
        s.offset = d.offset;
        return s;
    case ShapeType::Capsule:
        s.radius = d.radius;
        s.halfHeight = d.halfHeight;
        s.unitMass = capsuleMassProperties(d.radius, d.halfHeight);
        s.boundingRadius = d.halfHeight + d.radius;
        return s;
    case ShapeType::Convex:
    case ShapeType::Mesh:
        break;
    }
    if (d.type == ShapeType::Box) {
        Result<HalfEdgeMesh> box = buildHalfEdgeMesh(s.hull, d.where + ".half_extents");
        RUBBLE_TRY(box);
        s.halfEdge = std::move(*box);
        return s;
    }

    // Level geometry without a body to move keeps its own frame when it has no volume to centre.
    const bool levelOnly = d.type == ShapeType::Mesh && use.level && !use.moving;
    if (d.heightField) {
        RUBBLE_TRY(attachLevel(s, d));
        return s;
    }
    const std::string where = d.where + (d.type == ShapeType::Convex ? ".vertices" : ".file");
    Result<ConvexPolygons> hull = computeConvexHull(d.points, where);
    if (!hull && levelOnly) {
        RUBBLE_TRY(attachLevel(s, d));
        return s;
    }
    RUBBLE_TRY(hull);
    s.hull = std::move(*hull);
    const std::vector<glm::uvec3> hullTriangles = s.hull.triangles();
    s.unitMass = polyhedronMassProperties(s.hull.vertices, hullTriangles);
    if (d.type == ShapeType::Mesh) {
        s.mesh.vertices = d.points;
        s.mesh.triangles = d.triangles;
        if (isClosedMesh(s.mesh)) {
            const MassProperties own = polyhedronMassProperties(s.mesh.vertices, s.mesh.triangles);
            if (own.volume > 0.0) s.unitMass = own; // an inward-wound mesh keeps the hull's
        }
    }
    // The hull of a thin sliver passes Qhull but holds no volume worth simulating.
    const float extent = boundingRadiusOf(s.hull.vertices);
    if (!(s.unitMass.volume > 1e-9 * double(extent) * extent * extent)) {
        if (levelOnly) {
            s.hull = {};
            s.unitMass = {};
            RUBBLE_TRY(attachLevel(s, d));
            return s;
        }
        return makeError(ErrorKind::BadInput, where,
                         "the shape encloses no volume (its points are nearly coplanar)");
    }

    // Move the centre of mass to the origin; the file's frame keeps its orientation.
    s.centreShift = glm::vec3(s.unitMass.centre);
    for (glm::vec3& v : s.hull.vertices) v -= s.centreShift;
    for (glm::vec3& v : s.mesh.vertices) v -= s.centreShift;
    s.unitMass.centre = glm::dvec3(0.0);
    s.boundingRadius = boundingRadiusOf(s.hull.vertices);
    Result<HalfEdgeMesh> halfEdge = buildHalfEdgeMesh(s.hull, where);
    RUBBLE_TRY(halfEdge);
    s.halfEdge = std::move(*halfEdge);
    if (d.type == ShapeType::Mesh && use.level) {
        const float radius = s.boundingRadius;
        RUBBLE_TRY(attachLevel(s, d));
        s.boundingRadius = std::max(radius, s.boundingRadius);
    }
    return s;
}

ShapeGeometry geometryOf(const Shape& shape) {
    ShapeGeometry g;
    g.name = shape.name;
    g.type = shape.type;
    g.halfExtents = shape.halfExtents;
    g.radius = shape.radius;
    g.halfHeight = shape.halfHeight;
    g.normal = shape.normal;
    g.offset = shape.offset;
    g.boundingRadius = shape.boundingRadius;
    g.vertices = shape.hull.vertices;
    g.faces = shape.hull.faces;
    g.meshVertices = shape.mesh.vertices;
    g.meshTriangles = shape.mesh.triangles;
    return g;
}

} // namespace rubble
