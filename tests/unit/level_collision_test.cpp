// tests/unit/level_collision_test.cpp: host/collision/level_collision: the triangles a (body,
// level) pair keeps between steps (LevelCandidateCache) against a fresh hierarchy query each
// step: the same contacts while the body rests or slides, a new query when it leaves its region;
// and the manifolds it recycles (LevelManifoldCache) against fresh ones.
#include "host/collision/level_collision.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "host/collision/hull_data.h"
#include "host/core/math.h"
#include "host/geometry/shape.h"
#include "rubble/shared/broad_phase.h"
#include "support/level_cases.h"

namespace rubble {
namespace {

// A rolling grid of n x n quads of side `cell` centred on the origin, facing +y, heights up to
// `bump` m, so that a crate on it touches triangles of several normals.
LevelMesh rollingGrid(int n, float cell, float bump) {
    const TriangleMesh m = test::quadGrid(n, cell, [bump](float x, float z) {
        return bump * std::sin(1.3f * x) * std::cos(0.9f * z);
    });
    Result<LevelMesh> level = buildLevelMesh(m, "test");
    EXPECT_TRUE(level.ok());
    return std::move(*level);
}

Shape crateShape() {
    ShapeDesc d;
    d.type = ShapeType::Box;
    d.halfExtents = glm::vec3(0.5f);
    Result<Shape> s = buildShape(d);
    EXPECT_TRUE(s.ok());
    return std::move(*s);
}

constexpr float kMargin = 0.01f; // m, the pair's contact margin
const BodyPair kPair{0, 1};      // the level is body 0, the crate body 1

// One pair stepped through a list of crate poses, with the cache and with a fresh hierarchy
// query each step.
struct Pair {
    explicit Pair(LevelMesh mesh) : level(std::move(mesh)) {}

    LevelMesh level;
    Shape crate = crateShape();
    HullData hulls = flattenHulls(std::span<const Shape>(&crate, 1));
    shared::RigidTransform levelAt = transformAt(glm::vec3(0.0f), glm::quat(1, 0, 0, 0));
    LevelCandidateCache cache;
    LevelScratch cachedScratch, freshScratch;
    std::vector<shared::ContactManifold> cached, fresh;

    static shared::RigidTransform transformAt(glm::vec3 p, glm::quat q) {
        shared::BodyPose pose{};
        pose.position = toFloat4(p);
        pose.orientation = toFloat4(glm::normalize(q));
        return shared::transformOfPose(pose);
    }

    // One step with the crate at (p, q): both contact sets, and the triangles each tested.
    void step(glm::vec3 p, glm::quat q) {
        const shared::RigidTransform t = transformAt(p, q);
        const shared::BodyBox wb = shared::worldBoxItem(hulls.shapes[0], t, kMargin);
        const Aabb box{toVec3(wb.min), toVec3(wb.max)};
        cached.clear();
        fresh.clear();
        cache.beginStep();
        cache.candidates(kPair, level, levelQueryBox(levelAt, box), cachedScratch.triangles);
        collideLevelTriangles(level, levelAt, crate, t, cachedScratch.triangles, kMargin,
                              cachedScratch, cached);
        cache.endStep();
        collideLevel(level, levelAt, crate, t, box, kMargin, freshScratch, fresh);
    }

    // The cached step's triangles and contacts are the fresh ones (within 1e-5 m).
    void expectSameContacts(int step) const {
        ASSERT_EQ(cachedScratch.triangles, freshScratch.triangles) << "step " << step;
        ASSERT_EQ(cached.size(), fresh.size()) << "step " << step;
        for (std::size_t m = 0; m < fresh.size(); ++m) {
            ASSERT_EQ(cached[m].count, fresh[m].count) << "step " << step;
            EXPECT_NEAR(glm::distance(toVec3(cached[m].normal), toVec3(fresh[m].normal)), 0.0f,
                        1e-5f);
            for (std::uint32_t k = 0; k < fresh[m].count; ++k) {
                const shared::float4 a = cached[m].points[k], b = fresh[m].points[k];
                EXPECT_NEAR(glm::distance(toVec3(a), toVec3(b)), 0.0f, 1e-5f) << "step " << step;
                EXPECT_NEAR(a.w, b.w, 1e-5f) << "depth, step " << step;
                EXPECT_EQ(cached[m].features[k], fresh[m].features[k]) << "step " << step;
            }
        }
    }

    std::size_t contactCount() const {
        std::size_t n = 0;
        for (const shared::ContactManifold& m : fresh) n += m.count;
        return n;
    }
};

TEST(LevelCandidateCache, CrateRestingOnAMeshKeepsItsTrianglesAndContacts) {
    // A crate settling on rolling ground, trembling by a tenth of a millimetre and a few
    // thousandths of a radian each step, as an awake body at rest does: every step reuses the
    // first query and gives the contacts a fresh query gives.
    Pair pair(rollingGrid(24, 0.25f, 0.05f));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const glm::vec3 rest(0.3f, 0.47f, -0.2f);
    const glm::quat tilt = glm::angleAxis(0.05f, glm::normalize(glm::vec3(1, 0, 1)));
    int reused = 0;
    for (int i = 0; i < 60; ++i) {
        const glm::vec3 p = rest + 1e-4f * glm::vec3(u(rng), u(rng), u(rng));
        const glm::quat q = glm::angleAxis(3e-3f * u(rng), glm::vec3(0, 1, 0)) * tilt;
        pair.step(p, q);
        pair.expectSameContacts(i);
        ASSERT_GE(pair.contactCount(), 4u) << "the crate rests on the ground, step " << i;
        reused += int(pair.cache.reused());
    }
    EXPECT_EQ(reused, 59) << "every step after the first keeps its triangles";
}

TEST(LevelCandidateCache, SlidingCrateQueriesAgainWhenItLeavesItsRegion) {
    // A crate sliding 3 m across small triangles at 2 cm a step (1.2 m/s at 60 Hz), turning
    // slowly: it leaves its kept region every few steps and queries again, and no step misses
    // a triangle or a contact a fresh query finds.
    Pair pair(rollingGrid(40, 0.2f, 0.03f));
    int queried = 0, reused = 0;
    for (int i = 0; i < 150; ++i) {
        const glm::vec3 p(-1.5f + 0.02f * float(i), 0.48f, 0.1f);
        const glm::quat q = glm::angleAxis(0.002f * float(i), glm::vec3(0, 1, 0));
        pair.step(p, q);
        pair.expectSameContacts(i);
        ASSERT_GE(pair.contactCount(), 1u) << "step " << i;
        queried += int(pair.cache.queried());
        reused += int(pair.cache.reused());
    }
    // 3 m in regions 0.1 m wider on each side: a query every 5 or 6 steps.
    EXPECT_GE(queried, 25);
    EXPECT_LE(queried, 35);
    EXPECT_EQ(queried + reused, 150);
}

TEST(LevelCandidateCache, PairIsQueriedAgainPastTheMargin) {
    Pair pair(rollingGrid(24, 0.25f, 0.05f));
    const glm::vec3 p(0.0f, 0.47f, 0.0f);
    const glm::quat level(1, 0, 0, 0);
    pair.step(p, level);
    EXPECT_EQ(pair.cache.queried(), 1u);
    ASSERT_NE(pair.cache.keptBox(kPair), nullptr);
    const BvhBox first = *pair.cache.keptBox(kPair);

    // Moved by half the margin and turned by 0.05 rad about y (the box's sides move out by
    // another 0.025 m): within the margin, the kept box stays.
    const float within = 0.5f * kLevelCandidateMargin;
    pair.step(p + glm::vec3(within, 0.0f, -within), glm::angleAxis(0.05f, glm::vec3(0, 1, 0)));
    EXPECT_EQ(pair.cache.reused(), 1u);
    EXPECT_EQ(pair.cache.keptBox(kPair)->min, first.min);
    pair.expectSameContacts(1);

    // Moved past the margin along z: a new query, a new box around the new place.
    const glm::vec3 moved = p + glm::vec3(0.0f, 0.0f, 1.2f * kLevelCandidateMargin);
    pair.step(moved, level);
    EXPECT_EQ(pair.cache.queried(), 1u);
    EXPECT_EQ(pair.cache.reused(), 0u);
    EXPECT_NEAR(pair.cache.keptBox(kPair)->max.z - first.max.z, 1.2f * kLevelCandidateMargin,
                1e-5f);
    pair.expectSameContacts(2);

    // Turned in place by 20 degrees about y: the box's sides move out by 0.14 m, past the
    // margin: a new query.
    pair.step(moved, glm::angleAxis(glm::radians(20.0f), glm::vec3(0, 1, 0)));
    EXPECT_EQ(pair.cache.queried(), 1u);
    pair.expectSameContacts(3);

    // A step without the pair (separated or asleep) forgets it.
    pair.cache.beginStep();
    pair.cache.endStep();
    EXPECT_EQ(pair.cache.size(), 0u);
    EXPECT_EQ(pair.cache.keptBox(kPair), nullptr);
    pair.step(moved, level);
    EXPECT_EQ(pair.cache.queried(), 1u);
}

// One pair stepped through crate poses with recycling (LevelManifoldCache), as the narrow phase
// runs it, and collided afresh each step.
struct RecyclingPair {
    explicit RecyclingPair(LevelMesh mesh) : level(std::move(mesh)) {}

    LevelMesh level;
    Shape crate = crateShape();
    HullData hulls = flattenHulls(std::span<const Shape>(&crate, 1));
    shared::RigidTransform levelAt = Pair::transformAt(glm::vec3(0.0f), glm::quat(1, 0, 0, 0));
    LevelCandidateCache candidates;
    LevelManifoldCache manifolds;
    LevelScratch recycledScratch, freshScratch;
    std::vector<shared::ContactManifold> recycled, fresh;

    // One step with the crate at (p, q) and the pair's margin: whether it recycled.
    bool step(glm::vec3 p, glm::quat q, float margin = RUBBLE_CONTACT_MARGIN) {
        const shared::RigidTransform t = Pair::transformAt(p, q);
        const shared::BodyBox wb = shared::worldBoxItem(hulls.shapes[0], t, margin);
        const Aabb box{toVec3(wb.min), toVec3(wb.max)};
        const shared::RigidTransform inLevel = shared::transformRelative(levelAt, t);
        recycled.clear();
        fresh.clear();
        candidates.beginStep();
        manifolds.beginStep();
        const float radius = hulls.shapes[0].boundingRadius;
        const bool kept = manifolds.recycle(kPair, levelAt, inLevel, radius, margin, recycled);
        if (kept) {
            candidates.carry(kPair);
        } else {
            candidates.candidates(kPair, level, levelQueryBox(levelAt, box),
                                  recycledScratch.triangles);
            collideLevelTriangles(level, levelAt, crate, t, recycledScratch.triangles, margin,
                                  recycledScratch, recycled);
            manifolds.keep(kPair, levelAt, inLevel, margin, recycled);
        }
        candidates.endStep();
        manifolds.endStep();
        collideLevel(level, levelAt, crate, t, box, margin, freshScratch, fresh);
        return kept;
    }

    // Every fresh point has a recycled point of the same feature within `along` (m) of it and
    // within `tolerance` (m) of its depth, and the two have as many points, with normals within
    // `tolerance`.
    void expectCloseToFresh(float along, float tolerance, int step) const {
        std::size_t recycledPoints = 0, freshPoints = 0;
        for (const shared::ContactManifold& m : recycled) recycledPoints += m.count;
        for (const shared::ContactManifold& f : fresh) {
            freshPoints += f.count;
            for (std::uint32_t k = 0; k < f.count; ++k) {
                const shared::ContactManifold* match = nullptr;
                std::uint32_t at = 0;
                for (const shared::ContactManifold& m : recycled)
                    for (std::uint32_t j = 0; j < m.count; ++j)
                        if (m.features[j] == f.features[k]) match = &m, at = j;
                ASSERT_NE(match, nullptr) << "a fresh point is missing, step " << step;
                EXPECT_LT(glm::distance(toVec3(match->normal), toVec3(f.normal)), tolerance);
                EXPECT_LT(glm::distance(toVec3(match->points[at]), toVec3(f.points[k])), along)
                    << "step " << step;
                EXPECT_NEAR(match->points[at].w, f.points[k].w, tolerance)
                    << "depth, step " << step;
            }
        }
        EXPECT_EQ(recycledPoints, freshPoints) << "step " << step;
    }

    // The deepest recycled point is as deep as the deepest fresh one, within `tolerance` (m).
    void expectAsDeepAsFresh(float tolerance, int step) const {
        const auto deepest = [](const std::vector<shared::ContactManifold>& set) {
            float d = -1.0f;
            for (const shared::ContactManifold& m : set)
                for (std::uint32_t k = 0; k < m.count; ++k) d = std::max(d, m.points[k].w);
            return d;
        };
        EXPECT_NEAR(deepest(recycled), deepest(fresh), tolerance) << "step " << step;
    }
};

// The crate's resting height on a flat grid of 0.25 m quads at y = 0.
constexpr float kRestY = 0.5f - 0.001f;

TEST(LevelManifoldCache, CrateAtRestRecyclesUpToTheAgeLimit) {
    // A crate resting 1 mm deep on a flat grid, trembling by 20 micrometres: its manifold is
    // kept for RUBBLE_RECYCLE_MAX_AGE steps, then made afresh, and a recycled manifold is the
    // fresh one: the same features and depths (within a micrometre), the points within the
    // recycling limit (a point where an edge of the crate crosses a triangle's side slides along
    // the edge as the crate moves; a recycled one stays where it was made).
    RecyclingPair pair(rollingGrid(24, 0.25f, 0.0f));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const glm::quat turn = glm::angleAxis(0.3f, glm::vec3(0, 1, 0));
    int recycled = 0;
    for (int i = 0; i < 50; ++i) {
        const glm::vec3 p = glm::vec3(0.1f, kRestY, -0.05f) + 2e-5f * glm::vec3(u(rng), 0, u(rng));
        const bool kept = pair.step(p, turn);
        EXPECT_EQ(kept, i % int(RUBBLE_RECYCLE_MAX_AGE + 1) != 0) << "step " << i;
        recycled += int(kept);
        ASSERT_EQ(pair.fresh.size(), 1u) << "one manifold on a flat mesh";
        ASSERT_EQ(pair.fresh[0].count, 4u) << "its four corners";
        pair.expectCloseToFresh(RUBBLE_RECYCLE_DISTANCE, 1e-6f, i);
    }
    EXPECT_EQ(recycled, 40);
    EXPECT_EQ(pair.manifolds.size(), 1u);
}

TEST(LevelManifoldCache, RecycledCornersMoveWithTheBody) {
    // The crate slides 0.2 mm in one step, within the limit: the corners (points of the crate's
    // face clipped to the triangles) move with it and keep their depths, as the fresh ones do.
    RecyclingPair pair(rollingGrid(24, 0.25f, 0.0f));
    const glm::quat turn = glm::angleAxis(0.3f, glm::vec3(0, 1, 0));
    const glm::vec3 p(0.1f, kRestY, -0.05f);
    ASSERT_FALSE(pair.step(p, turn));
    ASSERT_TRUE(pair.step(p + glm::vec3(2e-4f, 0.0f, 0.0f), turn));
    pair.expectCloseToFresh(1e-6f, 1e-6f, 1);
    // Sinking by 0.2 mm deepens every point by as much.
    ASSERT_TRUE(pair.step(p + glm::vec3(0.0f, -2e-4f, 0.0f), turn));
    pair.expectCloseToFresh(1e-6f, 1e-6f, 2);
    EXPECT_NEAR(pair.recycled[0].points[0].w, 1.2e-3f, 1e-6f);
}

TEST(LevelManifoldCache, SlidingCrateGetsFreshManifoldsPastTheLimit) {
    // A crate sliding 3 m across rolling ground at 2 cm a step and one creeping at 0.1 mm a step:
    // the first never recycles; the second recycles only while within 0.25 mm of where its
    // manifolds were made. Both are always as deep as a fresh collision, to within the limit: no
    // point stays behind (sinks) or ahead (floats) of the body.
    for (const float stride : {0.02f, 1e-4f}) {
        RecyclingPair pair(rollingGrid(40, 0.2f, 0.03f));
        int recycled = 0;
        for (int i = 0; i < 150; ++i) {
            const glm::vec3 p(-1.5f + stride * float(i), 0.48f, 0.1f);
            const glm::quat q = glm::angleAxis(0.1f * stride * float(i), glm::vec3(0, 1, 0));
            recycled += int(pair.step(p, q));
            ASSERT_GE(pair.fresh.size(), 1u) << "step " << i;
            pair.expectAsDeepAsFresh(RUBBLE_RECYCLE_DISTANCE, i);
        }
        if (stride > RUBBLE_RECYCLE_DISTANCE)
            EXPECT_EQ(recycled, 0) << "stride " << stride;
        else
            EXPECT_EQ(recycled, 100) << "two of every three steps, stride " << stride;
    }
}

TEST(LevelManifoldCache, WideMarginTurnOrAbsenceMakesAFreshManifold) {
    RecyclingPair pair(rollingGrid(24, 0.25f, 0.0f));
    const glm::vec3 p(0.1f, kRestY, -0.05f);
    const glm::quat level(1, 0, 0, 0);
    // A body resting on a level starts each step with the step's gravity, g dt: its margin
    // holds g dt^2 = 2.7 mm at 60 Hz, every step alike, and its manifolds are recycled.
    const float resting = RUBBLE_CONTACT_MARGIN + 9.81f / 3600.0f;
    ASSERT_FALSE(pair.step(p, level, resting));
    EXPECT_TRUE(pair.step(p, level, resting));
    // A margin widened by more than the limit since they were made (the body speeds up by more
    // than 1.5 cm/s).
    EXPECT_FALSE(pair.step(p, level, resting + 2.0f * RUBBLE_RECYCLE_DISTANCE));
    EXPECT_TRUE(pair.step(p, level, resting + RUBBLE_RECYCLE_DISTANCE));
    // A turn of 1 mrad moves the crate's corners (0.87 m out) by 0.87 mm.
    EXPECT_FALSE(pair.step(p, glm::angleAxis(1e-3f, glm::vec3(0, 1, 0))));
    EXPECT_TRUE(pair.step(p, glm::angleAxis(1e-3f, glm::vec3(0, 1, 0))));
    // A step without the pair forgets it.
    pair.manifolds.beginStep();
    pair.manifolds.endStep();
    EXPECT_EQ(pair.manifolds.size(), 0u);
    EXPECT_FALSE(pair.step(p, glm::angleAxis(1e-3f, glm::vec3(0, 1, 0))));
    // Lifted clear of the margin: nothing to keep.
    EXPECT_FALSE(pair.step(p + glm::vec3(0.0f, 0.01f, 0.0f), level));
    EXPECT_TRUE(pair.recycled.empty());
    EXPECT_EQ(pair.manifolds.size(), 0u);
}

} // namespace
} // namespace rubble
