// tests/unit/hull_contact_test.cpp: manifolds of boxes and hulls (rubble/shared/hull_contact.h,
// run by the CPU stage and the device).
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "brute_force_sat.h"
#include "flat_hull.h"
#include "host/geometry/shape.h"
#include "random_hull.h"

namespace rubble {
namespace {

using test::collideHulls;
using test::collideHullsCached;
using test::FlatHull;
using test::HullContact;
using test::kContactMargin;
using test::LocalContact;
using test::runSat;
using test::separationAlong;

HalfEdgeMesh boxMesh(glm::vec3 h) {
    Result<HalfEdgeMesh> m = buildHalfEdgeMesh(boxPolygons(h), "box");
    EXPECT_TRUE(m.ok());
    return std::move(*m);
}

Transform pose(glm::vec3 t, glm::quat q = glm::quat(1, 0, 0, 0)) {
    return Transform{glm::mat3_cast(q), t};
}

// True when p lies inside the box (half extents h at pose t) grown by slop.
bool insideBox(glm::vec3 p, glm::vec3 h, const Transform& t, float slop) {
    const glm::vec3 local = t.applyInverse(p);
    return std::fabs(local.x) <= h.x + slop && std::fabs(local.y) <= h.y + slop &&
           std::fabs(local.z) <= h.z + slop;
}

TEST(HullContact, BoxOnBoxFaceToFaceGivesFourPoints) {
    const glm::vec3 h(0.5f);
    const HalfEdgeMesh box = boxMesh(h);
    // B sits on A, 1 cm deep, shifted sideways so the overlap is not the whole face.
    const Transform bInA = pose({0.2f, 0.99f, -0.1f});
    const HullContact c = collideHulls(box, box, bInA);
    ASSERT_FALSE(c.separated);
    ASSERT_EQ(c.contacts.count, 4u);
    EXPECT_NEAR(c.contacts.normal.y, 1.0f, 1e-6f);
    for (std::uint32_t i = 0; i < c.contacts.count; ++i) {
        const LocalContact& p = c.contacts.points[i];
        EXPECT_NEAR(p.depth, 0.01f, 1e-5f);
        EXPECT_NEAR(p.position.y, 0.495f, 1e-5f);
        EXPECT_TRUE(insideBox(p.position, h, Transform{}, 0.01f));
        EXPECT_TRUE(insideBox(p.position, h, bInA, 0.01f));
        for (std::uint32_t j = 0; j < i; ++j) EXPECT_NE(p.feature, c.contacts.points[j].feature);
    }
}

TEST(HullContact, BoxOnItsEdgeGivesTwoPoints) {
    const glm::vec3 h(0.5f);
    const HalfEdgeMesh box = boxMesh(h);
    // B turned 45 degrees about z rests on an edge, 1 cm into A's top face.
    const float edgeHeight = 0.5f * std::sqrt(2.0f);
    const glm::quat q = glm::angleAxis(glm::radians(45.0f), glm::vec3(0, 0, 1));
    const Transform bInA = pose({0.0f, 0.5f + edgeHeight - 0.01f, 0.0f}, q);
    const HullContact c = collideHulls(box, box, bInA);
    ASSERT_FALSE(c.separated);
    ASSERT_EQ(c.contacts.count, 2u);
    EXPECT_NEAR(c.contacts.normal.y, 1.0f, 1e-5f);
    for (std::uint32_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(c.contacts.points[i].depth, 0.01f, 1e-4f);
        EXPECT_NEAR(c.contacts.points[i].position.x, 0.0f, 1e-4f);
        EXPECT_NEAR(std::fabs(c.contacts.points[i].position.z), 0.5f, 1e-4f);
    }
}

TEST(HullContact, SeparatedBoxesGiveNothing) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    const HullContact c = collideHulls(box, box, pose({0.0f, 1.1f, 0.0f}));
    EXPECT_TRUE(c.separated);
    EXPECT_EQ(c.contacts.count, 0u);
    EXPECT_EQ(c.feature.feature, RUBBLE_SAT_FACE_A);
}

TEST(HullContact, GapWithinMarginIsANegativeDepth) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    const HullContact c = collideHulls(box, box, pose({0.0f, 1.002f, 0.0f}));
    ASSERT_FALSE(c.separated);
    ASSERT_EQ(c.contacts.count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i) EXPECT_NEAR(c.contacts.points[i].depth, -0.002f, 1e-5f);
}

TEST(HullContact, NormalPointsFromAToB) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    // B below A this time: the normal must point down.
    const HullContact c = collideHulls(box, box, pose({0.1f, -0.98f, 0.0f}));
    ASSERT_GT(c.contacts.count, 0u);
    EXPECT_NEAR(c.contacts.normal.y, -1.0f, 1e-6f);
}

TEST(HullContact, CrossedEdgesGiveOneEdgePoint) {
    const glm::vec3 h(0.5f);
    const HalfEdgeMesh box = boxMesh(h);
    // A's top edge along z; B stands on its edge along x, both turned 45 degrees: edges cross.
    const glm::quat qa = glm::angleAxis(glm::radians(45.0f), glm::vec3(0, 0, 1));
    const glm::quat qb = glm::angleAxis(glm::radians(45.0f), glm::vec3(1, 0, 0));
    const float e = 0.5f * std::sqrt(2.0f);
    const Transform ta = pose({0, 0, 0}, qa), tb = pose({0, 2 * e - 0.01f, 0}, qb);
    const HullContact c = collideHulls(box, box, relative(ta, tb));
    ASSERT_EQ(c.contacts.count, 1u);
    EXPECT_EQ(c.feature.feature, RUBBLE_SAT_EDGES);
    const glm::vec3 nWorld = ta.rotate(c.contacts.normal);
    EXPECT_NEAR(nWorld.y, 1.0f, 1e-4f);
    EXPECT_NEAR(c.contacts.points[0].depth, 0.01f, 1e-4f);
    const glm::vec3 pWorld = ta.apply(c.contacts.points[0].position);
    EXPECT_NEAR(pWorld.x, 0.0f, 1e-4f);
    EXPECT_NEAR(pWorld.z, 0.0f, 1e-4f);
    EXPECT_NEAR(pWorld.y, e - 0.005f, 1e-4f);
}

TEST(HullContact, FeatureIdsStayUnderSmallMotion) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    HullContact before = collideHulls(box, box, pose({0.2f, 0.99f, -0.1f}));
    ASSERT_EQ(before.contacts.count, 4u);
    const glm::quat q = glm::angleAxis(0.01f, glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)));
    HullContact after =
        collideHulls(box, box, pose({0.203f, 0.988f, -0.098f}, q), kContactMargin, before.feature);
    ASSERT_EQ(after.contacts.count, 4u);
    std::vector<std::uint32_t> a, b;
    for (std::uint32_t i = 0; i < 4; ++i) {
        a.push_back(before.contacts.points[i].feature);
        b.push_back(after.contacts.points[i].feature);
    }
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b);
}

TEST(HullContact, CachedFeatureIsReusedOnlyWhileThePoseStaysClose) {
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    shared::PairCache cache = shared::emptyPairCacheItem();
    const Transform rest = pose({0.2f, 0.99f, -0.1f});
    const HullContact first = collideHullsCached(box, box, rest, cache);
    ASSERT_TRUE(cache.reusable);
    EXPECT_EQ(cache.feature.feature, RUBBLE_SAT_FACE_A);
    EXPECT_EQ(toVec3(cache.reference.translation), rest.translation);

    // A tenth of a millimetre later: the same feature, the same points, no new reference.
    const Transform nudged = pose({0.2001f, 0.9899f, -0.1f});
    const HullContact reused = collideHullsCached(box, box, nudged, cache);
    const HullContact full = collideHulls(box, box, nudged);
    EXPECT_EQ(toVec3(cache.reference.translation), rest.translation);
    ASSERT_EQ(reused.contacts.count, full.contacts.count);
    for (std::uint32_t i = 0; i < full.contacts.count; ++i) {
        EXPECT_EQ(reused.contacts.points[i].feature, full.contacts.points[i].feature);
        EXPECT_NEAR(reused.contacts.points[i].depth, full.contacts.points[i].depth, 1e-6f);
    }

    // A pair 5 mm apart, then half a millimetre closer: the cached axis still separates them.
    shared::PairCache apart = shared::emptyPairCacheItem();
    EXPECT_TRUE(collideHullsCached(box, box, pose({0.2f, 1.005f, -0.1f}), apart).separated);
    const HullContact closer = collideHullsCached(box, box, pose({0.2f, 1.0045f, -0.1f}), apart);
    EXPECT_TRUE(closer.separated);
    EXPECT_EQ(apart.reference.translation.y, 1.005f);

    // Turned by 5 degrees: a full test and a new reference.
    const Transform turned =
        pose({0.2f, 0.99f, -0.1f}, glm::angleAxis(glm::radians(5.0f), glm::vec3(0, 0, 1)));
    collideHullsCached(box, box, turned, cache);
    EXPECT_EQ(toMat3(cache.reference.rotation), turned.rotation);
    EXPECT_GT(first.contacts.count, 0u);
}

TEST(HullContact, FacesWithManyVerticesClipOnTheHeap) {
    // A 100-sided prism (disc) resting on a box and the box on it: faces of 100 vertices.
    Result<Shape> disc = test::discShape();
    ASSERT_TRUE(disc.ok()) << disc.error().describe();
    ASSERT_EQ(disc->halfEdge.faceCount(), 102u);
    const HalfEdgeMesh box = boxMesh(glm::vec3(0.5f));
    // Disc on the box, 5 mm deep: its whole bottom face overlaps the top of the box.
    HullContact c = collideHulls(box, disc->halfEdge, pose({0.0f, 0.595f, 0.0f}));
    ASSERT_EQ(c.contacts.count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i) EXPECT_NEAR(c.contacts.points[i].depth, 0.005f, 1e-5f);
    // The box on the disc.
    c = collideHulls(disc->halfEdge, box, pose({0.1f, 0.595f, 0.0f}));
    ASSERT_EQ(c.contacts.count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i) EXPECT_NEAR(c.contacts.points[i].depth, 0.005f, 1e-5f);
}

// The largest distance of p outside the hull's face planes (negative inside), hull frame.
float outside(const HalfEdgeMesh& m, glm::vec3 p) {
    float d = -1e30f;
    for (const HalfEdgeFace& f : m.faces) d = std::max(d, glm::dot(f.normal, p) - f.offset);
    return d;
}

TEST(HullContact, RandomHullManifoldsLieInBothShapes) {
    std::mt19937 rng(31);
    std::vector<Shape> pool;
    for (int i = 0; i < 40; ++i) pool.push_back(test::randomHull(rng));
    std::vector<FlatHull> flat;
    for (const Shape& s : pool) flat.emplace_back(s.halfEdge);
    std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int failures = 0, withContacts = 0, faceContacts = 0, edgeContacts = 0;
    auto fail = [&](int i, const std::string& what) {
        if (++failures <= 5) ADD_FAILURE() << "pair " << i << ": " << what;
    };
    for (int i = 0; i < 3000; ++i) {
        const std::size_t ia = pick(rng), ib = pick(rng);
        const Shape &sa = pool[ia], &sb = pool[ib];
        const HalfEdgeMesh &ma = sa.halfEdge, &mb = sb.halfEdge;
        const FlatHull &a = flat[ia], &b = flat[ib];
        // Touching, then pushed up to 2 cm into contact or 3 mm apart.
        const glm::quat q = test::randomRotation(rng);
        const glm::vec3 dir = test::randomDirection(rng);
        float lo = 0.0f, hi = sa.boundingRadius + sb.boundingRadius;
        for (int k = 0; k < 24; ++k) {
            const float mid = 0.5f * (lo + hi);
            (runSat(a, b, test::makeTransform(dir * mid, q)).separated ? hi : lo) = mid;
        }
        const Transform bInA = test::makeTransform(dir * (lo + 0.003f - 0.023f * u01(rng)), q);
        const HullContact c = collideHulls(a, b, bInA);
        if (c.separated || c.contacts.count == 0) continue;
        ++withContacts;
        faceContacts += c.feature.feature != RUBBLE_SAT_EDGES;
        edgeContacts += c.feature.feature == RUBBLE_SAT_EDGES;
        const glm::vec3 n = c.contacts.normal;
        if (std::fabs(glm::length(n) - 1.0f) > 1e-5f) fail(i, "normal is not unit");
        // From A to B: B lies further along n than A does, and n is nearly the axis of least
        // penetration (the feature choice may prefer a face that is a little deeper).
        const float along = separationAlong(a, b, bInA, n);
        const float against = separationAlong(a, b, bInA, -n);
        const shared::SatResult sat = runSat(a, b, bInA, kContactMargin);
        if (!(along > against)) fail(i, "normal points from B to A");
        if (sat.separation > along + 0.16f * std::fabs(along) + 0.0051f)
            fail(i, "normal is far from the axis of least penetration");
        for (std::uint32_t k = 0; k < c.contacts.count; ++k) {
            const LocalContact& p = c.contacts.points[k];
            // Midway between the surfaces, moved along the normal: within half the depth (or
            // half the gap) of each surface where the faces are not parallel.
            const float slop = 0.5f * std::fabs(p.depth) + 1e-4f;
            const float outA = outside(ma, p.position),
                        outB = outside(mb, bInA.applyInverse(p.position));
            if (outA > slop || outB > slop)
                fail(i, "point outside a shape: " + std::to_string(outA) + ", " +
                            std::to_string(outB) + " (depth " + std::to_string(p.depth) + ")");
            if (p.depth > 0.02f + 1e-3f || p.depth < -kContactMargin - 1e-5f)
                fail(i, "depth out of range: " + std::to_string(p.depth));
            for (std::uint32_t j = 0; j < k; ++j)
                if (c.contacts.points[j].feature == p.feature) fail(i, "repeated feature id");
        }
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GT(withContacts, 2000);
    EXPECT_GT(faceContacts, 500);
    EXPECT_GT(edgeContacts, 200);
}

// Crates of a grid thrown apart (scenes/explosion.json): two boxes turned by at most 3 degrees
// against each other, neighbours along one, two or three axes (touching to 3 cm apart along
// those, anywhere along the others), with a margin grown by the speed of the pair (up to
// 0.4 m), met twice: once by the full test, then a little later, moved within the cache's reuse
// limits. Nearly parallel edges give an edge axis that swings with the slightest turn; every
// manifold must still be one of the SAT: no point deeper than the least penetration over all
// candidate axes (brute force), and a normal along which the boxes overlap no more than that.
TEST(HullContact, ManifoldsOfFastSlightlyTurnedBoxesAgreeWithTheSat) {
    std::mt19937 rng(35);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    int failures = 0, checked = 0, reused = 0, edgeContacts = 0;
    auto fail = [&](int i, const std::string& what) {
        if (++failures <= 5) ADD_FAILURE() << "pair " << i << ": " << what;
    };
    // A manifold at bInA against the brute-force SAT: depths and normal within the feature
    // choice's tolerance (a face up to 10% + 2.5 mm deeper than the best axis is kept).
    auto check = [&](int i, const char* path, const HalfEdgeMesh& a, const HalfEdgeMesh& b,
                     const FlatHull& fa, const FlatHull& fb, const Transform& bInA,
                     const HullContact& c) {
        if (c.separated || c.contacts.count == 0) return;
        ++checked;
        const float best = test::bruteForceSeparation(a, b, bInA).all();
        const float tolerance = 0.16f * std::fabs(best) + 0.0051f;
        float deepest = -1e30f;
        for (std::uint32_t k = 0; k < c.contacts.count; ++k)
            deepest = std::max(deepest, c.contacts.points[k].depth);
        const float along = separationAlong(fa, fb, bInA, c.contacts.normal);
        char text[240];
        std::snprintf(text, sizeof text,
                      "%s: deepest point %.4f m, normal (%.3f %.3f %.3f) overlaps by %.4f m; "
                      "the SAT's depth is %.4f m",
                      path, double(deepest), double(c.contacts.normal.x),
                      double(c.contacts.normal.y), double(c.contacts.normal.z), double(-along),
                      double(-best));
        if (deepest > -best + tolerance) fail(i, std::string("too deep, ") + text);
        if (along < best - tolerance) fail(i, std::string("wrong normal, ") + text);
    };
    for (int i = 0; i < 4000; ++i) {
        const glm::vec3 ha(0.1f + 0.3f * u01(rng), 0.1f + 0.3f * u01(rng), 0.1f + 0.3f * u01(rng));
        const glm::vec3 hb(0.1f + 0.3f * u01(rng), 0.1f + 0.3f * u01(rng), 0.1f + 0.3f * u01(rng));
        const HalfEdgeMesh a = boxMesh(ha), b = boxMesh(hb);
        const FlatHull fa(a), fb(b);
        const glm::quat turn = glm::angleAxis(0.05f * u01(rng), test::randomDirection(rng));
        glm::vec3 offset(0.0f);
        const int stacked = 1 + int(u01(rng) * 7.0f) % 7; // a non-empty set of axes
        for (int k = 0; k < 3; ++k) {
            const float side = u01(rng) < 0.5f ? -1.0f : 1.0f, reach = ha[k] + hb[k];
            offset[k] =
                side * ((stacked >> k) & 1 ? reach - 0.01f + 0.04f * u01(rng) : reach * u01(rng));
        }
        const Transform first = pose(offset, turn);
        const float margin = kContactMargin + 0.4f * u01(rng);
        // Moved within the reuse limits: under a millimetre and under a quarter degree.
        const glm::quat nudge = glm::angleAxis(0.004f * u01(rng), test::randomDirection(rng));
        const Transform later =
            pose(offset + test::randomDirection(rng) * (0.0009f * u01(rng)), nudge * turn);
        shared::PairCache cache = shared::emptyPairCacheItem();
        collideHullsCached(fa, fb, first, cache, margin);
        const glm::vec3 reference = toVec3(cache.reference.translation);
        const HullContact c = collideHullsCached(fa, fb, later, cache, margin);
        reused += toVec3(cache.reference.translation) == reference;
        edgeContacts += c.feature.feature == RUBBLE_SAT_EDGES && c.contacts.count > 0;
        check(i, "cached", a, b, fa, fb, later, c);
        check(i, "full test", a, b, fa, fb, later, collideHulls(fa, fb, later, margin));
    }
    EXPECT_EQ(failures, 0);
    // The draw covers what it is for: contacts, reused features, edge contacts.
    EXPECT_GT(checked, 2000);
    EXPECT_GT(reused, 1000);
    EXPECT_GT(edgeContacts, 50);
}

} // namespace
} // namespace rubble
