// tests/unit/random_hull.h: seeded random convex hulls and poses for the collision property tests,
// a hull with many-vertex faces, and the shipped OBJ meshes as shapes.
#pragma once

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "transform.h"
#include "host/geometry/obj_mesh.h"
#include "host/geometry/shape.h"

namespace rubble::test {

/// A random convex shape of 4 to 60 points: in a ball, on a sphere, or in a stretched box, so
/// that hulls range from tetrahedra through slabs to round ones with ~100 faces.
inline Shape randomHull(std::mt19937& rng) {
    std::uniform_int_distribution<int> count(4, 60), style(0, 2);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), stretch(0.3f, 1.5f);
    std::normal_distribution<float> gauss;
    for (;;) {
        ShapeDesc d;
        d.type = ShapeType::Convex;
        d.where = "random";
        const int n = count(rng), s = style(rng);
        const glm::vec3 scale(stretch(rng), stretch(rng), stretch(rng));
        for (int i = 0; i < n; ++i) {
            glm::vec3 p;
            if (s == 0) {
                do p = glm::vec3(unit(rng), unit(rng), unit(rng));
                while (glm::dot(p, p) > 1.0f);
            } else if (s == 1) {
                p = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
            } else {
                p = glm::vec3(unit(rng), unit(rng), unit(rng));
            }
            d.points.push_back(p * scale);
        }
        Result<Shape> shape = buildShape(d);
        if (shape.ok()) return std::move(*shape); // a degenerate draw is drawn again
    }
}

/// A uniformly random rotation.
inline glm::quat randomRotation(std::mt19937& rng) {
    std::normal_distribution<float> gauss;
    return glm::normalize(glm::quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)));
}

/// A random unit vector.
inline glm::vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<float> gauss;
    glm::vec3 v;
    do v = glm::vec3(gauss(rng), gauss(rng), gauss(rng));
    while (glm::dot(v, v) < 1e-6f);
    return glm::normalize(v);
}

inline Transform makeTransform(glm::vec3 translation, glm::quat rotation) {
    return Transform{glm::mat3_cast(rotation), translation};
}

/// A 100-sided prism (a disc of radius 0.8 m, 0.2 m thick, centred at the origin): two faces of
/// 100 vertices, for the paths that clip or reduce many points.
inline Result<Shape> discShape() {
    ShapeDesc d;
    d.type = ShapeType::Convex;
    d.where = "disc";
    for (int i = 0; i < 100; ++i) {
        const float a = 2.0f * 3.14159265f * float(i) / 100.0f;
        d.points.emplace_back(0.8f * std::cos(a), -0.1f, 0.8f * std::sin(a));
        d.points.emplace_back(0.8f * std::cos(a), 0.1f, 0.8f * std::sin(a));
    }
    return buildShape(d);
}

/// scenes/meshes/<file> scaled by `scale`, as a mesh shape (it collides as its hull).
inline Result<Shape> shippedMeshShape(const char* file, float scale) {
    const std::string path = std::string(RUBBLE_SOURCE_DIR) + "/scenes/meshes/" + file;
    Result<TriangleMesh> mesh = loadObjMesh(path, scale, file);
    if (!mesh) return mesh.error();
    ShapeDesc d;
    d.type = ShapeType::Mesh;
    d.where = file;
    d.points = mesh->vertices;
    d.triangles = mesh->triangles;
    return buildShape(d);
}

} // namespace rubble::test
