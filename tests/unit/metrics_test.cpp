// tests/unit/metrics_test.cpp: host/io/metrics: percentiles by selection equal those of a sorted
// copy; the recorder's fixed-memory histogram comes within half a bin of them.
#include <algorithm>
#include <cmath>
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

// The recorder's histogram: percentiles within half a bin of the exact ones, over timings spread
// across six decades, with zeros (a CPU run's device times) reported as 0.
TEST(Metrics, TimeHistogramPercentilesAreWithinHalfABin) {
    std::mt19937 rng(11);
    std::lognormal_distribution<double> ms(0.0, 2.5);
    std::vector<double> v(20000);
    TimeHistogram h;
    for (double& x : v) {
        x = ms(rng);
        h.add(x);
    }
    EXPECT_EQ(h.count(), 20000);
    const double halfBin = std::sqrt(TimeHistogram::kRatio) - 1.0;
    for (const double q : {0.0, 0.1, 0.5, 0.9, 0.99, 1.0}) {
        const double exact = sortedPercentile(v, q);
        EXPECT_NEAR(h.percentile(q), exact, exact * halfBin * 1.0001) << q;
    }
    TimeHistogram zeros;
    for (int i = 0; i < 10; ++i) zeros.add(0.0);
    zeros.add(3.0);
    EXPECT_EQ(zeros.percentile(0.5), 0.0);
    EXPECT_NEAR(zeros.percentile(1.0), 3.0, 3.0 * halfBin);
    EXPECT_EQ(TimeHistogram().percentile(0.5), 0.0);
}

} // namespace
} // namespace rubble
