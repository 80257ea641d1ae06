// tests/support/pair_cases.h: seeded random shape pairs for the narrow-phase twin test of the
// device kernel against the CPU stage: boxes, random convex hulls, spheres and planes at
// random relative poses that touch, leave a gap within the margin, overlap deeply, cross two
// edges, or are apart; each pair as two bodies of a stage input.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "host/collision/hull_data.h"
#include "host/core/math.h"
#include "host/world/world_build.h"
#include "rubble/shared/narrow_phase.h"
#include "support/stage_input.h"
#include "unit/random_hull.h"

namespace rubble::test {

/// How the two shapes of a case were placed.
enum class PairKind { Touching, Gap, Deep, CrossedEdges, Apart };

inline const char* toString(PairKind k) {
    switch (k) {
    case PairKind::Touching:
        return "touching";
    case PairKind::Gap:
        return "gap within the margin";
    case PairKind::Deep:
        return "deep";
    case PairKind::CrossedEdges:
        return "crossed edges";
    case PairKind::Apart:
        return "apart";
    }
    return "?";
}

/// Body 2i and body 2i + 1 of `in` are case i's pair; kinds[i] says how they were placed.
struct PairCases {
    StageInput in;
    std::vector<PairKind> kinds;
};

namespace detail {

inline shared::RigidTransform transformOfDesc(const BodyDesc& b) {
    return shared::transformOfPose(shared::BodyPose{toFloat4(b.position), toFloat4(b.orientation)});
}

// The shapes flattened for the narrow phase, with clipping buffers for their largest face.
struct FlatShapes {
    HullData data;
    ClipSpace clip;
    explicit FlatShapes(std::span<const Shape> shapes)
        : data(flattenHulls(shapes)), clip(data.largestFace) {}
};

// Whether shapes sa and sb touch (a contact with margin 0) with b moved to a's position + t u.
inline bool touchesAt(FlatShapes& f, std::uint32_t sa, const BodyDesc& a, std::uint32_t sb,
                      BodyDesc b, glm::vec3 u, float t) {
    b.position = a.position + u * t;
    shared::PairCache cache = shared::emptyPairCacheItem();
    const shared::ClipBuffers buffers = f.clip.buffers();
    return shared::collideShapesClippingInItem(hullArraysOf(f.data), f.data.shapes[sa],
                                               transformOfDesc(a), f.data.shapes[sb],
                                               transformOfDesc(b), &cache, 0.0f, buffers)
               .count > 0;
}

// The distance along u at which b, coming from far away, first touches a (bisection).
inline float touchingDistance(FlatShapes& f, const std::vector<Shape>& shapes, std::uint32_t sa,
                              const BodyDesc& a, std::uint32_t sb, const BodyDesc& b, glm::vec3 u) {
    const Shape &shapeA = shapes[sa], &shapeB = shapes[sb];
    float lo = 0.0f, hi = shapeA.boundingRadius + shapeB.boundingRadius + 0.1f;
    if (shapeA.type == ShapeType::Plane || shapeB.type == ShapeType::Plane)
        hi = std::max(shapeA.boundingRadius, shapeB.boundingRadius) + 0.1f;
    if (!touchesAt(f, sa, a, sb, b, u, lo)) return lo; // a plane seen from its solid side
    for (int i = 0; i < 40; ++i) {
        const float mid = 0.5f * (lo + hi);
        (touchesAt(f, sa, a, sb, b, u, mid) ? lo : hi) = mid;
    }
    return 0.5f * (lo + hi);
}

/// Places case i's pair: body b along u from a (against a plane's normal when either is one) at
/// the touching distance moved by `kind`, with a random velocity, and appends both bodies.
inline void placePair(PairCases& c, FlatShapes& flat, std::mt19937& rng, int i, PairKind kind,
                      std::uint32_t sa, BodyDesc& a, std::uint32_t sb, BodyDesc& b, glm::vec3 u) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    const Shape& shapeA = c.in.shapes[sa];
    const Shape& shapeB = c.in.shapes[sb];
    // A plane is static; along its normal the other shape meets it face on.
    if (shapeA.type == ShapeType::Plane)
        u = glm::mat3_cast(a.orientation) * shapeA.normal;
    else if (shapeB.type == ShapeType::Plane)
        u = -(glm::mat3_cast(b.orientation) * shapeB.normal);
    float t = touchingDistance(flat, c.in.shapes, sa, a, sb, b, u);
    const float smaller = std::min(shapeA.type == ShapeType::Plane ? 1e9f : shapeA.boundingRadius,
                                   shapeB.type == ShapeType::Plane ? 1e9f : shapeB.boundingRadius);
    switch (kind) {
    case PairKind::Touching:
    case PairKind::CrossedEdges:
        t += 0.001f * sym(rng);
        break;
    case PairKind::Gap:
        t += 0.004f * unit(rng);
        break;
    case PairKind::Deep:
        t -= 0.3f * smaller * unit(rng);
        break;
    case PairKind::Apart:
        t += 0.01f + unit(rng);
        break;
    }
    b.position = a.position + u * t;
    b.linearVelocity = randomDirection(rng) * (1.2f * unit(rng));
    a.isStatic = shapeA.type == ShapeType::Plane;
    b.isStatic = shapeB.type == ShapeType::Plane;
    a.mass = b.mass = 1.0f;
    a.shape = sa;
    b.shape = sb;
    for (BodyDesc* d : {&a, &b}) {
        d->name = "case " + std::to_string(i) + (d == &a ? " a" : " b");
        c.in.scene.bodies.push_back(*d);
        appendBodyArrays(c.in.bodies, *d, c.in.shapes[d->shape]);
        c.in.names.push_back(d->name);
    }
    c.kinds.push_back(kind);
}

} // namespace detail

/// `count` random pairs from `seed`. Shapes: boxes (a cube, a slab, a bar), 12 random hulls,
/// two OBJ meshes (scenes/meshes/rock.obj and l_block.obj, as their hulls), spheres of three
/// radii, a plane. Kinds: two fifths touching (found by bisection, then up to
/// 1 mm in or out), a fifth with a gap of 0 to 4 mm, a fifth deep (up to 30% of the smaller
/// shape's radius in), the rest crossed box edges or apart. Body b moves with up to 1.2 m/s
/// relative to a at dt = 1/60, so that the pair margins differ (up to 2 cm more).
inline PairCases makePairCases(std::uint32_t seed, int count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    PairCases c;
    Scene& scene = c.in.scene;
    scene.materials.push_back(MaterialDesc{});
    auto addShape = [&](Result<Shape> s) {
        if (!s) abortOn(s.error());
        c.in.shapes.push_back(std::move(*s));
        return std::uint32_t(c.in.shapes.size() - 1);
    };
    auto box = [&](glm::vec3 h) {
        ShapeDesc d;
        d.type = ShapeType::Box;
        d.halfExtents = h;
        d.where = "box";
        return addShape(buildShape(d));
    };
    std::vector<std::uint32_t> boxes = {box(glm::vec3(0.5f)), box({0.8f, 0.1f, 0.6f}),
                                        box({0.15f, 0.15f, 0.9f})};
    std::vector<std::uint32_t> hulls = boxes;
    for (int i = 0; i < 12; ++i) hulls.push_back(addShape(randomHull(rng)));
    // Meshes collide as their hulls.
    for (const char* file : {"rock.obj", "l_block.obj"})
        hulls.push_back(addShape(shippedMeshShape(file, 0.8f)));
    std::vector<std::uint32_t> spheres;
    for (float r : {0.2f, 0.5f, 0.9f}) {
        ShapeDesc d;
        d.type = ShapeType::Sphere;
        d.radius = r;
        d.where = "sphere";
        spheres.push_back(addShape(buildShape(d)));
    }
    ShapeDesc planeDesc;
    planeDesc.type = ShapeType::Plane;
    planeDesc.where = "plane";
    const std::uint32_t planeShape = addShape(buildShape(planeDesc));

    detail::FlatShapes flat(c.in.shapes);
    auto pick = [&](const std::vector<std::uint32_t>& v) {
        return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
    };
    for (int i = 0; i < count; ++i) {
        // Shapes: mostly hull pairs, then spheres and planes in every role.
        const float r = unit(rng);
        std::uint32_t sa, sb;
        if (r < 0.55f)
            sa = pick(hulls), sb = pick(hulls);
        else if (r < 0.67f)
            sa = pick(hulls), sb = pick(spheres);
        else if (r < 0.72f)
            sa = pick(spheres), sb = pick(spheres);
        else if (r < 0.92f)
            sa = planeShape, sb = pick(hulls);
        else
            sa = planeShape, sb = pick(spheres);
        if (unit(rng) < 0.5f) std::swap(sa, sb);
        const float k = unit(rng);
        PairKind kind = k < 0.4f   ? PairKind::Touching
                        : k < 0.6f ? PairKind::Gap
                        : k < 0.8f ? PairKind::Deep
                        : k < 0.9f ? PairKind::CrossedEdges
                                   : PairKind::Apart;
        BodyDesc a, b;
        a.position = glm::vec3(sym(rng), sym(rng), sym(rng)) * 5.0f;
        a.orientation = randomRotation(rng);
        b.orientation = randomRotation(rng);
        glm::vec3 u = randomDirection(rng);
        if (kind == PairKind::CrossedEdges) {
            // Two boxes, each resting on an edge, the edges crossed at right angles (a few
            // degrees off), b coming down from above.
            sa = pick(boxes);
            sb = pick(boxes);
            const float tilt = glm::radians(4.0f);
            a.orientation =
                glm::angleAxis(glm::radians(45.0f) + tilt * sym(rng), glm::vec3(1, 0, 0)) *
                glm::angleAxis(tilt * sym(rng), glm::vec3(0, 1, 0));
            b.orientation =
                glm::angleAxis(glm::radians(90.0f) + tilt * sym(rng), glm::vec3(0, 1, 0)) *
                glm::angleAxis(glm::radians(45.0f) + tilt * sym(rng), glm::vec3(1, 0, 0));
            u = glm::normalize(glm::vec3(0.05f * sym(rng), 1.0f, 0.05f * sym(rng)));
        }
        detail::placePair(c, flat, rng, i, kind, sa, a, sb, b, u);
    }
    c.in.surfaces = bodySurfaces(scene.materials, c.in.bodies.materialOf);
    return c;
}

/// `count` random pairs with a capsule from `seed`: capsules of three sizes against capsules,
/// spheres, boxes, random hulls and a plane, placed as makePairCases places its pairs (touching,
/// a gap within the margin, deep, apart; a capsule lying on a box face in a tenth of them).
inline PairCases makeCapsuleCases(std::uint32_t seed, int count) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    PairCases c;
    Scene& scene = c.in.scene;
    scene.materials.push_back(MaterialDesc{});
    auto addShape = [&](const ShapeDesc& d) {
        Result<Shape> s = buildShape(d);
        if (!s) abortOn(s.error());
        c.in.shapes.push_back(std::move(*s));
        return std::uint32_t(c.in.shapes.size() - 1);
    };
    std::vector<std::uint32_t> capsules, others;
    for (const glm::vec2 rh :
         {glm::vec2(0.1f, 0.3f), glm::vec2(0.25f, 0.5f), glm::vec2(0.4f, 0.1f)}) {
        ShapeDesc d;
        d.type = ShapeType::Capsule;
        d.radius = rh.x;
        d.halfHeight = rh.y;
        d.where = "capsule";
        capsules.push_back(addShape(d));
    }
    std::vector<std::uint32_t> boxes;
    for (const glm::vec3 h : {glm::vec3(0.5f), glm::vec3(0.8f, 0.1f, 0.6f)}) {
        ShapeDesc d;
        d.type = ShapeType::Box;
        d.halfExtents = h;
        d.where = "box";
        boxes.push_back(addShape(d));
    }
    others = boxes;
    for (int i = 0; i < 4; ++i) {
        c.in.shapes.push_back(randomHull(rng));
        others.push_back(std::uint32_t(c.in.shapes.size() - 1));
    }
    ShapeDesc sphere;
    sphere.type = ShapeType::Sphere;
    sphere.radius = 0.3f;
    sphere.where = "sphere";
    others.push_back(addShape(sphere));
    ShapeDesc planeDesc;
    planeDesc.type = ShapeType::Plane;
    planeDesc.where = "plane";
    const std::uint32_t planeShape = addShape(planeDesc);
    others.insert(others.end(), capsules.begin(), capsules.end());
    others.push_back(planeShape);

    detail::FlatShapes flat(c.in.shapes);
    auto pick = [&](const std::vector<std::uint32_t>& v) {
        return v[std::uniform_int_distribution<std::size_t>(0, v.size() - 1)(rng)];
    };
    for (int i = 0; i < count; ++i) {
        std::uint32_t sa = pick(capsules), sb = pick(others);
        const bool lying = unit(rng) < 0.1f;
        if (lying) sb = pick(boxes);
        if (unit(rng) < 0.5f) std::swap(sa, sb);
        const float k = unit(rng);
        const PairKind kind = k < 0.4f    ? PairKind::Touching
                              : k < 0.6f  ? PairKind::Gap
                              : k < 0.85f ? PairKind::Deep
                                          : PairKind::Apart;
        BodyDesc a, b;
        a.position = glm::vec3(sym(rng), sym(rng), sym(rng)) * 5.0f;
        a.orientation = randomRotation(rng);
        b.orientation = randomRotation(rng);
        glm::vec3 u = randomDirection(rng);
        const Shape& shapeA = c.in.shapes[sa];
        if (lying) {
            // The box level, the capsule lying on its top a few tenths of a degree off level.
            BodyDesc& box = shapeA.type == ShapeType::Box ? a : b;
            BodyDesc& cap = shapeA.type == ShapeType::Box ? b : a;
            box.orientation = glm::quat(1, 0, 0, 0);
            cap.orientation =
                glm::angleAxis(glm::radians(90.0f + 0.3f * sym(rng)), glm::vec3(0, 0, 1)) *
                glm::angleAxis(glm::radians(180.0f) * sym(rng), glm::vec3(1, 0, 0));
            u = glm::vec3(0.1f * sym(rng), shapeA.type == ShapeType::Box ? 1.0f : -1.0f,
                          0.1f * sym(rng));
            u = glm::normalize(u);
        }
        detail::placePair(c, flat, rng, i, kind, sa, a, sb, b, u);
    }
    c.in.surfaces = bodySurfaces(scene.materials, c.in.bodies.materialOf);
    return c;
}

} // namespace rubble::test
