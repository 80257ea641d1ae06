// tests/unit/sat_test.cpp: the separating axis test (rubble/shared/sat.h, run by the CPU stage
// and the device) against brute force on random hulls at random poses: the verdict, the depth,
// and the pruned edge query against every edge pair.

#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "brute_force_sat.h"
#include "flat_hull.h"
#include "random_hull.h"

namespace rubble {
namespace {

using test::BruteForce;
using test::bruteForceSeparation;
using test::FlatHull;
using test::makeTransform;
using test::queryEdgeDirections;
using test::randomDirection;
using test::randomHull;
using test::randomRotation;
using test::runSat;
using test::separationAlong;

// A pool of random hulls, built once.
const std::vector<Shape>& hullPool() {
    static const std::vector<Shape> pool = [] {
        std::mt19937 rng(20130307);
        std::vector<Shape> hulls;
        for (int i = 0; i < 120; ++i) hulls.push_back(randomHull(rng));
        return hulls;
    }();
    return pool;
}

// The pool flattened as the narrow phase reads it.
const std::vector<FlatHull>& flatPool() {
    static const std::vector<FlatHull> flat = [] {
        std::vector<FlatHull> hulls;
        for (const Shape& s : hullPool()) hulls.emplace_back(s.halfEdge);
        return hulls;
    }();
    return flat;
}

// b's pose in a's frame: touching (found by bisection on the SAT's verdict along a direction),
// deeply overlapping, or anywhere from overlapping to apart.
Transform randomPose(std::size_t ia, std::size_t ib, int kind, std::mt19937& rng) {
    const Shape &a = hullPool()[ia], &b = hullPool()[ib];
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const glm::quat q = randomRotation(rng);
    const glm::vec3 dir = randomDirection(rng);
    const float reach = a.boundingRadius + b.boundingRadius;
    if (kind == 0) return makeTransform(dir * (u01(rng) * 1.2f * reach), q);
    if (kind == 1) return makeTransform(dir * (u01(rng) * 0.3f * reach), q);
    float lo = 0.0f, hi = reach * 1.01f;
    for (int i = 0; i < 20; ++i) {
        const float mid = 0.5f * (lo + hi);
        if (runSat(flatPool()[ia], flatPool()[ib], makeTransform(dir * mid, q)).separated)
            hi = mid;
        else
            lo = mid;
    }
    // Up to a millimetre into contact, or out of it.
    const float step = u01(rng) * 1e-3f;
    return makeTransform(dir * (kind == 2 ? lo - step : hi + step), q);
}

// The 10,000 pairs both property tests use: hull indices and b's pose in a's frame; a quarter
// anywhere, a quarter deep, half touching (just overlapping or just apart).
struct Case {
    std::size_t a, b;
    Transform bInA;
};

const std::vector<Case>& randomCases() {
    static const std::vector<Case> cases = [] {
        const std::vector<Shape>& pool = hullPool();
        std::mt19937 rng(42);
        std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
        std::vector<Case> out;
        for (int i = 0; i < 10000; ++i) {
            const std::size_t a = pick(rng), b = pick(rng);
            out.push_back(Case{a, b, randomPose(a, b, i % 4, rng)});
        }
        return out;
    }();
    return cases;
}

// Collects failures and reports the first few in full.
class Failures {
  public:
    void add(int pair, const std::string& what) {
        if (++count_ <= 5) ADD_FAILURE() << "pair " << pair << ": " << what;
    }
    int count() const { return count_; }

  private:
    int count_ = 0;
};

TEST(Sat, MatchesBruteForceOnTenThousandRandomPairs) {
    const std::vector<Shape>& pool = hullPool();
    constexpr float kDepthTolerance = 1e-4f;
    // Near a verdict's boundary float round-off may tip either way.
    constexpr float kVerdictBand = 1e-5f;
    Failures failures;
    int separated = 0, touching = 0, deep = 0, edgeWins = 0;
    const std::vector<Case>& cases = randomCases();
    for (int i = 0; i < int(cases.size()); ++i) {
        const HalfEdgeMesh& ma = pool[cases[i].a].halfEdge;
        const HalfEdgeMesh& mb = pool[cases[i].b].halfEdge;
        const FlatHull& a = flatPool()[cases[i].a];
        const FlatHull& b = flatPool()[cases[i].b];
        const Transform& bInA = cases[i].bInA;
        const BruteForce brute = bruteForceSeparation(ma, mb, bInA);
        const shared::SatResult sat = runSat(a, b, bInA);
        separated += sat.separated;
        touching += std::fabs(brute.all()) < 1e-3f;
        deep += brute.all() < -0.2f;
        edgeWins += !sat.separated && sat.feature == RUBBLE_SAT_EDGES;
        char text[200];
        std::snprintf(text, sizeof text, "brute %.7g, sat %.7g (%s)", double(brute.all()),
                      double(sat.separation), sat.separated ? "separated" : "overlapping");
        if (std::fabs(brute.all()) > kVerdictBand && sat.separated != (brute.all() > 0.0f))
            failures.add(i, std::string("verdict differs: ") + text);
        if (!sat.separated && std::fabs(sat.separation - brute.all()) > kDepthTolerance)
            failures.add(i, std::string("depth differs: ") + text);
        if (sat.separated &&
            (sat.separation <= 0.0f || brute.all() < sat.separation - kDepthTolerance))
            failures.add(i, std::string("separating axis is not one: ") + text);
        // The reported axis and separation agree with the support points.
        const float along = separationAlong(a, b, bInA, toVec3(sat.axis));
        if (std::fabs(along - sat.separation) > kDepthTolerance)
            failures.add(i, "axis disagrees with its separation: " + std::to_string(along));

        // The pruned edge query (every pair, no early out) against every edge pair: with the
        // faces, the same answer; alone, never above the unpruned maximum.
        const shared::EdgeQuery pruned = queryEdgeDirections(a, b, bInA);
        const float withPruned = std::max(brute.faces, pruned.separation);
        if (brute.all() < 0.0f && std::fabs(withPruned - brute.all()) > kDepthTolerance)
            failures.add(i, "pruned edges give " + std::to_string(withPruned) + ", unpruned " +
                                std::to_string(brute.all()));
        if (pruned.separation > brute.edges + kDepthTolerance)
            failures.add(i, "a pruned edge axis beats every unpruned one");
    }
    EXPECT_EQ(failures.count(), 0);
    // The draw covers every case.
    EXPECT_GT(separated, 2000);
    EXPECT_GT(touching, 2000);
    EXPECT_GT(deep, 1000);
    EXPECT_GT(edgeWins, 500);
}

TEST(Sat, PrunedEdgeAxesAreSupportAxes) {
    // Every pruned candidate is a real axis: its edge-point separation is the support one.
    Failures failures;
    const std::vector<Case>& cases = randomCases();
    int checked = 0; // cases with a candidate edge pair left after the pruning
    for (int i = 0; i < int(cases.size()); i += 10) {
        const FlatHull& a = flatPool()[cases[i].a];
        const FlatHull& b = flatPool()[cases[i].b];
        const Transform& bInA = cases[i].bInA;
        const shared::EdgeQuery e = queryEdgeDirections(a, b, bInA);
        if (!(e.separation > -1e30f)) continue;
        ++checked;
        if (std::fabs(e.separation - separationAlong(a, b, bInA, toVec3(e.axis))) > 1e-4f)
            failures.add(i, "pruned edge separation is not the support separation");
    }
    EXPECT_EQ(failures.count(), 0);
    // A pruning that left no candidate would pass the loop above untested.
    std::printf("[ pruned edges ] %d of %d cases had a candidate\n", checked,
                (int(cases.size()) + 9) / 10);
    EXPECT_GT(checked, 500);
}

TEST(Sat, HintGivesTheSameVerdict) {
    std::mt19937 rng(99);
    std::uniform_int_distribution<std::size_t> pick(0, hullPool().size() - 1);
    Failures failures;
    for (int i = 0; i < 2000; ++i) {
        const std::size_t ia = pick(rng), ib = pick(rng);
        const FlatHull &a = flatPool()[ia], &b = flatPool()[ib];
        const Transform bInA = randomPose(ia, ib, i % 4, rng);
        const shared::SatResult cold = runSat(a, b, bInA);
        // The hint of a slightly different pose, as from the last step.
        const Transform moved{bInA.rotation, bInA.translation + randomDirection(rng) * 0.01f};
        const shared::SatResult last = runSat(a, b, moved);
        const shared::SatResult warm = runSat(
            a, b, bInA, 0.0f, shared::makeSatHint(last.feature, last.indexA, last.indexB, 0u));
        if (std::fabs(cold.separation) > 1e-5f && cold.separated != warm.separated)
            failures.add(i, "the hint changed the verdict");
        if (!cold.separated && std::fabs(cold.separation - warm.separation) > 1e-6f)
            failures.add(i, "the hint changed the depth");
    }
    EXPECT_EQ(failures.count(), 0);
}

TEST(Sat, OverlapOfBoxes) {
    Result<HalfEdgeMesh> mesh = buildHalfEdgeMesh(boxPolygons(glm::vec3(0.5f)), "box");
    ASSERT_TRUE(mesh.ok());
    const FlatHull box(*mesh);
    EXPECT_TRUE(runSat(box, box, Transform{glm::mat3(1.0f), {1.01f, 0, 0}}).separated);
    const shared::SatResult s = runSat(box, box, Transform{glm::mat3(1.0f), {0.9f, 0.2f, 0}});
    ASSERT_FALSE(s.separated);
    EXPECT_EQ(s.feature, RUBBLE_SAT_FACE_A);
    EXPECT_NEAR(s.separation, -0.1f, 1e-6f);
    EXPECT_NEAR(s.axis.x, 1.0f, 1e-6f);
}

} // namespace
} // namespace rubble
