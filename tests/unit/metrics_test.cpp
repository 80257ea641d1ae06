// tests/unit/metrics_test.cpp: host/io/metrics: percentiles by selection equal those of a sorted
// copy.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "host/io/metrics.h"

namespace rubble {
namespace {

double sortedPercentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    const double pos = q * double(v.size() - 1);
    const std::size_t lo = std::size_t(pos), hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (v[hi] - v[lo]) * (pos - double(lo));
}

TEST(Metrics, PercentileBySelectionMatchesSorting) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> ms(0.1, 40.0);
    for (const std::size_t n : {1u, 2u, 3u, 10u, 1001u, 30000u}) {
        std::vector<double> v(n);
        for (double& x : v) x = ms(rng);
        v[n / 2] = v[0]; // a tie
        for (const double q : {0.0, 0.1, 0.5, 0.9, 0.99, 1.0}) {
            std::vector<double> copy = v;
            EXPECT_EQ(percentile(copy, q), sortedPercentile(v, q)) << n << " " << q;
        }
    }
    std::vector<double> empty;
    EXPECT_EQ(percentile(empty, 0.5), 0.0);
}

} // namespace
} // namespace rubble
