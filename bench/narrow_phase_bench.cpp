// bench/narrow_phase_bench.cpp: throughput of the CPU collision stages: SAT and manifolds of the
// shared narrow phase (rubble/shared/hull_contact.h, as SatCollision runs it) for box-box and
// 20-face hull pairs, and both stages over 16,384 resting boxes. Figures and the command are in
// docs/collision.md.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/gtc/quaternion.hpp>

#include "host/collision/hull_data.h"
#include "host/collision/sat_collision.h"
#include "host/geometry/shape.h"
#include "rubble/shared/hull_contact.h"
#include "support/stage_input.h"
#include "unit/flat_hull.h"

namespace rubble {
namespace {

constexpr int kPairs = 1024;

struct PairSet {
    HullData hull;                             ///< the shape, flattened
    std::vector<shared::RigidTransform> poses; ///< b's pose in a's frame, two copies of the shape
    shared::Hull of() const { return shared::hullOfItem(hullArraysOf(hull), hull.shapes[0]); }
};

Shape boxShape() {
    ShapeDesc d;
    d.type = ShapeType::Box;
    d.halfExtents = glm::vec3(0.5f);
    return std::move(buildShape(d).value());
}

// An icosahedron with its vertices jittered by 5%: 12 vertices, 30 edges, 20 faces.
Shape hull20Shape() {
    const float t = (1.0f + std::sqrt(5.0f)) * 0.5f;
    const glm::vec3 ico[12] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::mt19937 rng(20);
    std::uniform_real_distribution<float> jitter(0.95f, 1.05f);
    ShapeDesc d;
    d.type = ShapeType::Convex;
    d.where = "bench";
    for (const glm::vec3& v : ico) d.points.push_back(glm::normalize(v) * 0.6f * jitter(rng));
    return std::move(buildShape(d).value());
}

// Pairs in contact as a pile has them: b at a random orientation, moved along a random
// direction until the hulls just touch, then 0 to 2 cm into each other.
PairSet touchingPairs(const Shape& shape) {
    PairSet set{flattenHulls(std::span<const Shape>(&shape, 1)), {}};
    const shared::Hull m = set.of();
    std::mt19937 rng(1);
    std::normal_distribution<float> gauss;
    std::uniform_real_distribution<float> depth(0.0f, 0.02f);
    for (int i = 0; i < kPairs; ++i) {
        const glm::quat q =
            glm::normalize(glm::quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)));
        const glm::vec3 dir = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
        float lo = 0.0f, hi = 2.0f * shape.boundingRadius;
        for (int k = 0; k < 24; ++k) {
            const float mid = 0.5f * (lo + hi);
            const shared::RigidTransform t = test::rigidOf(Transform{glm::mat3_cast(q), dir * mid});
            (shared::runSatItem(m, m, t, 0.0f, test::noHint()).separated ? hi : lo) = mid;
        }
        set.poses.push_back(test::rigidOf(Transform{glm::mat3_cast(q), dir * (lo - depth(rng))}));
    }
    return set;
}

const PairSet& boxPairs() {
    static const PairSet set = touchingPairs(boxShape());
    return set;
}

const PairSet& hullPairs() {
    static const PairSet set = touchingPairs(hull20Shape());
    return set;
}

void runSatOver(benchmark::State& state, const PairSet& set) {
    const shared::Hull m = set.of();
    for (auto _ : state)
        for (const shared::RigidTransform& t : set.poses) {
            const shared::SatResult r =
                shared::runSatItem(m, m, t, RUBBLE_CONTACT_MARGIN, test::noHint());
            benchmark::DoNotOptimize(r.separation);
        }
    state.SetItemsProcessed(state.iterations() * std::int64_t(set.poses.size()));
}

// Manifolds from scratch every time, or through each pair's cache as a resting pile has them
// (the pose unchanged since the last full test: one support query, then the clipping).
void runManifoldsOver(benchmark::State& state, const PairSet& set, bool cached) {
    const shared::Hull m = set.of();
    ClipSpace clip(set.hull.largestFace);
    const shared::ClipBuffers buffers = clip.buffers();
    std::vector<shared::PairCache> caches(set.poses.size(), shared::emptyPairCacheItem());
    for (std::size_t i = 0; i < set.poses.size(); ++i)
        shared::collideHullsCachedItem(m, m, set.poses[i], &caches[i], RUBBLE_CONTACT_MARGIN,
                                       buffers);
    for (auto _ : state)
        for (std::size_t i = 0; i < set.poses.size(); ++i) {
            const shared::HullContact c =
                cached ? shared::collideHullsCachedItem(m, m, set.poses[i], &caches[i],
                                                        RUBBLE_CONTACT_MARGIN, buffers)
                       : shared::collideHullsItem(m, m, set.poses[i], RUBBLE_CONTACT_MARGIN,
                                                  test::noHint(), buffers);
            benchmark::DoNotOptimize(c.contacts.count);
        }
    state.SetItemsProcessed(state.iterations() * std::int64_t(set.poses.size()));
}

void BM_SatBoxBox(benchmark::State& s) {
    runSatOver(s, boxPairs());
}
void BM_SatHull20(benchmark::State& s) {
    runSatOver(s, hullPairs());
}
void BM_ManifoldBoxBox(benchmark::State& s) {
    runManifoldsOver(s, boxPairs(), false);
}
void BM_ManifoldBoxBoxCached(benchmark::State& s) {
    runManifoldsOver(s, boxPairs(), true);
}
void BM_ManifoldHull20(benchmark::State& s) {
    runManifoldsOver(s, hullPairs(), false);
}
void BM_ManifoldHull20Cached(benchmark::State& s) {
    runManifoldsOver(s, hullPairs(), true);
}

BENCHMARK(BM_SatBoxBox);
BENCHMARK(BM_SatHull20);
BENCHMARK(BM_ManifoldBoxBox);
BENCHMARK(BM_ManifoldBoxBoxCached);
BENCHMARK(BM_ManifoldHull20);
BENCHMARK(BM_ManifoldHull20Cached);

// 16,384 unit boxes at rest: 32 x 16 x 32 columns on a floor plane, each box on the one below,
// columns 1.2 m apart, turned by up to 0.05 rad.
test::StageInput restingBoxes() {
    const std::string scene = R"({"format": "rubble-scene", "version": 1, "name": "resting_16k",
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1.0, "count": [32, 16, 32],
                      "origin": [-18.6, 0.5, -18.6], "spacing": [1.2, 1.0, 1.2],
                      "rotation_jitter": 0.05, "seed": 1, "name_prefix": "d"}]})";
    return test::stageInput(scene);
}

void BM_BroadPhaseResting16k(benchmark::State& state) {
    const test::StageInput in = restingBoxes();
    SatCollision sat(ContactForm::Manifolds);
    StepContacts contacts;
    for (auto _ : state) {
        if (!sat.broadPhase(in.collisionScene(), in.bodies.view(), in.params(), contacts).ok())
            return state.SkipWithError("the broad phase failed");
        benchmark::DoNotOptimize(contacts.pairs.data());
    }
    state.counters["pairs"] = double(contacts.pairs.size());
    state.counters["bodies"] = double(in.bodies.count());
}
BENCHMARK(BM_BroadPhaseResting16k)->Unit(benchmark::kMillisecond);

void BM_NarrowPhaseResting16k(benchmark::State& state) {
    const test::StageInput in = restingBoxes();
    SatCollision sat(ContactForm::Manifolds);
    StepContacts contacts;
    const StepParams params = in.params();
    // warm: every pair has its cached feature
    if (!sat.broadPhase(in.collisionScene(), in.bodies.view(), params, contacts).ok() ||
        !sat.narrowPhase(in.collisionScene(), in.bodies.view(), params, contacts).ok())
        return state.SkipWithError("the collision stages failed");
    for (auto _ : state) {
        if (!sat.narrowPhase(in.collisionScene(), in.bodies.view(), params, contacts).ok())
            return state.SkipWithError("the narrow phase failed");
        benchmark::DoNotOptimize(contacts.manifolds.data());
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(contacts.pairs.size()));
    state.counters["contacts"] = double(contacts.contactCount);
}
BENCHMARK(BM_NarrowPhaseResting16k)->Unit(benchmark::kMillisecond);

// The broad phase alone on the 65,536 boxes of scenes/bench/debris_64k.json at their start:
// 64 x 16 x 64 unit boxes 1.2 m apart, turned by up to 0.1 rad.
void BM_FindPairsDebris64k(benchmark::State& state) {
    std::vector<Aabb> boxes;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> grow(0.0f, 0.07f);
    for (int x = 0; x < 64; ++x)
        for (int y = 0; y < 16; ++y)
            for (int z = 0; z < 64; ++z) {
                const glm::vec3 c(x * 1.2f, 2.0f + y * 1.2f, z * 1.2f);
                const glm::vec3 h(0.5f + grow(rng), 0.5f + grow(rng), 0.5f + grow(rng));
                boxes.push_back(Aabb{c - h, c + h});
            }
    const std::vector<std::uint8_t> flags(boxes.size(), 0);
    std::vector<BodyPair> pairs;
    BroadPhaseScratch scratch;
    for (auto _ : state) {
        findPairs(boxes, flags, {}, pairs, scratch);
        benchmark::DoNotOptimize(pairs.data());
    }
    state.counters["entries"] = double(scratch.entries.size());
}
BENCHMARK(BM_FindPairsDebris64k)->Unit(benchmark::kMillisecond);

} // namespace
} // namespace rubble

BENCHMARK_MAIN();
