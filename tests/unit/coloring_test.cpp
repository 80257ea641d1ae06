// tests/unit/coloring_test.cpp: host/gpu/coloring: the greedy batches of the device's
// Gauss-Seidel solve, against a brute-force check of what a batch may hold.
#include "host/gpu/coloring.h"

#include <algorithm>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace rubble {
namespace {

struct Element {
    std::uint32_t a, b;
    bool movesA, movesB;
};

// 3,000 random elements over 400 bodies, a tenth of them not moving: every element once, no
// two elements of a color on one moving body, first fit's bound of 2 d - 1 colors for the
// largest degree d, and the same result for the same input.
TEST(Coloring, NoColorSharesAMovingBody) {
    std::mt19937 rng(5);
    std::uniform_int_distribution<std::uint32_t> body(0, 399);
    std::vector<bool> moving(400);
    for (std::size_t i = 0; i < moving.size(); ++i) moving[i] = rng() % 10 != 0;
    std::vector<Element> elements;
    for (int i = 0; i < 3000; ++i) {
        const std::uint32_t a = body(rng), b = (a + 1 + body(rng) % 399) % 400;
        elements.push_back({a, b, moving[a], moving[b]});
    }
    for (const bool bySupport : {false, true}) {
        gpu::Coloring coloring, again;
        for (gpu::Coloring* c : {&coloring, &again}) {
            c->begin(400);
            if (bySupport) {
                std::vector<gpu::ColorElement> list;
                for (std::uint32_t i = 0; i < elements.size(); ++i)
                    list.push_back(
                        {i, elements[i].a, elements[i].b, elements[i].movesA, elements[i].movesB});
                c->addBySupport(list);
            } else {
                for (std::uint32_t i = 0; i < elements.size(); ++i)
                    c->add(i, elements[i].a, elements[i].b, elements[i].movesA, elements[i].movesB);
            }
            c->finish();
        }
        EXPECT_TRUE(std::equal(coloring.order().begin(), coloring.order().end(),
                               again.order().begin(), again.order().end()));
        std::vector<std::uint32_t> seen(elements.size(), 0), degree(400, 0);
        for (const Element& e : elements) {
            if (e.movesA) ++degree[e.a];
            if (e.movesB) ++degree[e.b];
        }
        for (std::uint32_t c = 0; c < coloring.colors(); ++c) {
            std::set<std::uint32_t> bodies;
            for (std::uint32_t i = coloring.start()[c]; i < coloring.start()[c + 1]; ++i) {
                const Element& e = elements[coloring.order()[i]];
                ++seen[coloring.order()[i]];
                if (e.movesA) {
                    EXPECT_TRUE(bodies.insert(e.a).second) << "color " << c;
                }
                if (e.movesB) {
                    EXPECT_TRUE(bodies.insert(e.b).second) << "color " << c;
                }
            }
        }
        EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](std::uint32_t n) { return n == 1; }));
        const std::uint32_t d = *std::max_element(degree.begin(), degree.end());
        EXPECT_LE(coloring.colors(), 2 * d - 1);
        std::printf("[ coloring ] %s: %u colors for a largest degree of %u\n",
                    bySupport ? "by support" : "first fit", coloring.colors(), d);
    }
}

// A column of six bodies on a static floor, its elements given from the top down, after three
// elements elsewhere have taken colors 0 - 2: colored from the bottom up, each element takes the
// color after the one below it (0 1 2 0 1 2), so that a sweep of the colors in order carries the
// floor's support three bodies up; first fit in the given order alternates (0 1 0 1 0 1 from the
// top), two bodies a sweep.
TEST(Coloring, BySupportWalksUpAColumnThroughTheColors) {
    constexpr std::uint32_t kFloor = 0, kStar = 20;
    auto column = [] {
        std::vector<gpu::ColorElement> list;
        for (std::uint32_t k = 6; k-- > 0;) // element k joins body k (or the floor) and k + 1
            list.push_back({k, k == 0 ? kFloor : k, k + 1, k != 0, true});
        return list;
    };
    auto colorOf = [](const gpu::Coloring& c, std::uint32_t id) {
        for (std::uint32_t k = 0; k < c.colors(); ++k)
            for (std::uint32_t i = c.start()[k]; i < c.start()[k + 1]; ++i)
                if (c.order()[i] == id) return k;
        return 99u;
    };
    gpu::Coloring bySupport, firstFit;
    for (gpu::Coloring* c : {&bySupport, &firstFit}) {
        c->begin(30);
        for (std::uint32_t i = 0; i < 3; ++i) c->add(100 + i, kStar, kStar + 1 + i, true, true);
    }
    bySupport.addBySupport(column());
    bySupport.finish();
    for (const gpu::ColorElement& e : column()) firstFit.add(e.id, e.a, e.b, e.movesA, e.movesB);
    firstFit.finish();
    for (std::uint32_t k = 0; k < 6; ++k) {
        EXPECT_EQ(colorOf(bySupport, k), k % 3) << "element " << k << " by support";
        EXPECT_EQ(colorOf(firstFit, k), (5 - k) % 2) << "element " << k << " first fit";
    }
    EXPECT_EQ(bySupport.colors(), 3u);
}

// More than 64 colors: a body shared by 150 elements takes 150 colors (its masks widen), and
// elements on bodies that do not move all take color 0.
TEST(Coloring, WidensPast64ColorsAndLeavesStillBodiesOut) {
    gpu::Coloring c;
    c.begin(300);
    for (std::uint32_t i = 0; i < 150; ++i) c.add(i, 0, i + 1, true, true);
    for (std::uint32_t i = 0; i < 100; ++i) c.add(1000 + i, 200, 201 + i % 50, false, false);
    c.finish();
    EXPECT_EQ(c.colors(), 150u);
    // Color 0 holds the first star element and every still one.
    EXPECT_EQ(c.start()[1] - c.start()[0], 101u);
}

} // namespace
} // namespace rubble
