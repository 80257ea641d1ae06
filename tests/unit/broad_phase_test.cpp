// tests/unit/broad_phase_test.cpp: host/collision/broad_phase against brute force O(n^2).
#include "host/collision/broad_phase.h"

#include <algorithm>

#include <random>

#include <gtest/gtest.h>

#include "rubble/shared/broad_phase.h"

namespace rubble {
namespace {

struct RandomSet {
    std::vector<Aabb> boxes;
    std::vector<std::uint8_t> flags;
    std::vector<PlaneProxy> planes;
};

// n boxes of mixed sizes (a few large ones) in a region, some inactive, some planes.
RandomSet randomSet(std::mt19937& rng, std::uint32_t n, float region) {
    std::uniform_real_distribution<float> pos(-region, region), size(0.05f, 1.0f), u01(0.0f, 1.0f);
    RandomSet s;
    for (std::uint32_t i = 0; i < n; ++i) {
        const glm::vec3 c(pos(rng), pos(rng), pos(rng));
        glm::vec3 h(size(rng), size(rng), size(rng));
        if (u01(rng) < 0.02f) h *= 10.0f; // a few large bodies across many columns
        s.boxes.push_back(Aabb{c - h, c + h});
        std::uint8_t f = u01(rng) < 0.3f ? kBroadPhaseInactive : 0;
        if (u01(rng) < 0.01f) {
            f = kBroadPhaseInactive | kBroadPhaseNoBox;
            const glm::vec3 normal = glm::normalize(glm::vec3(pos(rng), region, pos(rng)));
            s.planes.push_back(PlaneProxy{i, normal, pos(rng) * 0.5f});
        }
        s.flags.push_back(f);
    }
    return s;
}

TEST(BroadPhase, MatchesBruteForceOnRandomBoxes) {
    std::mt19937 rng(1234);
    BroadPhaseScratch scratch;
    std::size_t total = 0;
    for (int round = 0; round < 40; ++round) {
        const std::uint32_t n = 1 + std::uint32_t(rng() % 800);
        const RandomSet s = randomSet(rng, n, 2.0f + float(round % 5) * 3.0f);
        std::vector<BodyPair> fast, brute;
        findPairs(s.boxes, s.flags, s.planes, fast, scratch);
        findPairsBruteForce(s.boxes, s.flags, s.planes, brute);
        ASSERT_EQ(fast, brute) << "round " << round << ", " << n << " boxes";
        total += fast.size();
    }
    EXPECT_GT(total, 10000u); // the sets are dense enough to mean something
}

TEST(BroadPhase, KeptOrderGivesTheSameAnswerStepAfterStep) {
    // The same bodies drifting and tumbling over many steps, one becoming a plane's slot on the
    // way: the sweep starts from the previous order and must still match brute force.
    std::mt19937 rng(77);
    RandomSet s = randomSet(rng, 600, 4.0f);
    std::uniform_real_distribution<float> step(-0.2f, 0.2f);
    BroadPhaseScratch scratch;
    for (int t = 0; t < 30; ++t) {
        for (Aabb& b : s.boxes) {
            const glm::vec3 d(step(rng), step(rng), step(rng));
            b.min += d;
            b.max += d;
        }
        if (t == 10) s.flags[5] = kBroadPhaseInactive | kBroadPhaseNoBox;
        if (t == 20) s.flags[5] = 0;
        std::vector<BodyPair> fast, brute;
        findPairs(s.boxes, s.flags, s.planes, fast, scratch);
        findPairsBruteForce(s.boxes, s.flags, s.planes, brute);
        ASSERT_EQ(fast, brute) << "step " << t;
    }
}

TEST(BroadPhase, PairsAreSortedAndOrdered) {
    std::mt19937 rng(5);
    const RandomSet s = randomSet(rng, 500, 3.0f);
    std::vector<BodyPair> pairs;
    BroadPhaseScratch scratch;
    findPairs(s.boxes, s.flags, s.planes, pairs, scratch);
    ASSERT_FALSE(pairs.empty());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        EXPECT_LT(pairs[i].a, pairs[i].b);
        if (i > 0) {
            EXPECT_LT(pairs[i - 1], pairs[i]);
        }
        EXPECT_FALSE((s.flags[pairs[i].a] & kBroadPhaseInactive) &&
                     (s.flags[pairs[i].b] & kBroadPhaseInactive));
    }
}

TEST(BroadPhase, TouchingBoxesPairAndPlanesReachEveryBodyBelowThem) {
    const std::vector<Aabb> boxes{{{0, 0, 0}, {1, 1, 1}},
                                  {{1, 0, 0}, {2, 1, 1}},  // touches box 0
                                  {{0, 0, 0}, {0, 0, 0}},  // the plane's slot
                                  {{5, 3, 5}, {6, 4, 6}}}; // above the plane y = 2.5
    const std::vector<std::uint8_t> flags{0, 0, kBroadPhaseInactive | kBroadPhaseNoBox, 0};
    const std::vector<PlaneProxy> planes{{2, {0, 1, 0}, 2.5f}};
    std::vector<BodyPair> pairs;
    BroadPhaseScratch scratch;
    findPairs(boxes, flags, planes, pairs, scratch);
    const std::vector<BodyPair> expected{{0, 1}, {0, 2}, {1, 2}};
    EXPECT_EQ(pairs, expected);
}

TEST(BroadPhase, RestingGridIsLinear) {
    // A 64 x 4 x 64 grid of unit boxes 1.2 m apart: only the floor plane pairs with them.
    std::vector<Aabb> boxes;
    std::vector<std::uint8_t> flags;
    for (int x = 0; x < 64; ++x)
        for (int y = 0; y < 4; ++y)
            for (int z = 0; z < 64; ++z) {
                const glm::vec3 c(x * 1.2f, 0.5f + y * 1.0f, z * 1.2f);
                boxes.push_back(Aabb{c - glm::vec3(0.5f), c + glm::vec3(0.5f)});
                flags.push_back(0);
            }
    std::vector<BodyPair> pairs;
    BroadPhaseScratch scratch;
    findPairs(boxes, flags, {}, pairs, scratch);
    // Stacked boxes touch their neighbours above and below: 64 * 64 * 3 pairs.
    EXPECT_EQ(pairs.size(), 64u * 64u * 3u);
    // Columns are wider than the boxes: each box sits in at most four.
    EXPECT_LE(scratch.entries.size(), 4 * boxes.size());
}

// The device's search for last step's pair (shared::findPairItem, findPairFromItem) against a
// scan: the index of the pair, or the count when the list does not hold it, from any start at or
// before its place.
TEST(BroadPhase, PairSearchMatchesAScan) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::uint32_t> body(0, 40);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<shared::BodyPairRecord> pairs;
        const std::uint32_t n = std::uint32_t(trial % 50);
        for (std::uint32_t k = 0; k < n; ++k) {
            std::uint32_t a = body(rng), b = body(rng);
            if (a == b) continue;
            pairs.push_back({std::min(a, b), std::max(a, b)});
        }
        auto before = [](shared::BodyPairRecord x, shared::BodyPairRecord y) {
            return x.a < y.a || (x.a == y.a && x.b < y.b);
        };
        std::sort(pairs.begin(), pairs.end(), before);
        pairs.erase(std::unique(pairs.begin(), pairs.end(),
                                [](auto x, auto y) { return x.a == y.a && x.b == y.b; }),
                    pairs.end());
        const auto count = std::uint32_t(pairs.size());
        for (std::uint32_t a = 0; a <= 41; ++a)
            for (std::uint32_t b = a + 1; b <= 41; b += 3) {
                const shared::BodyPairRecord pair{a, b};
                std::uint32_t scan = count;
                for (std::uint32_t k = 0; k < count; ++k)
                    if (pairs[k].a == a && pairs[k].b == b) scan = k;
                ASSERT_EQ(shared::findPairItem(pair, count, pairs.data()), scan)
                    << "pair (" << a << ", " << b << ") among " << count;
                // From any index at or before the pair's place (the pairs before it sort
                // before it), as collideShapes searches from the last pair it found.
                std::uint32_t place = 0;
                while (place < count && before(pairs[place], pair)) ++place;
                for (std::uint32_t from = 0; from <= place; ++from) {
                    ASSERT_EQ(shared::lowerPairItem(pair, from, count, pairs.data()), place);
                    ASSERT_EQ(shared::findPairFromItem(pair, from, count, pairs.data()), scan)
                        << "pair (" << a << ", " << b << ") from " << from;
                }
            }
    }
}

} // namespace
} // namespace rubble
