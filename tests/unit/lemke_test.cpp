// tests/unit/lemke_test.cpp: Lemke's method against brute-force enumeration of complementary
// bases on small random LCPs (positive semidefinite, singular, degenerate, P-matrices), and its
// errors.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "host/dynamics/lemke.h"

namespace rubble {
namespace {

using Matrix = std::vector<double>;

// Every solution of the LCP found by trying each set of basic z's: M_aa z_a = -q_a solved by
// elimination (singular sets skipped), kept when z >= 0 and w >= 0 within `tolerance`.
std::vector<std::vector<double>> bruteForceSolutions(const Matrix& m, const std::vector<double>& q,
                                                     double tolerance) {
    const std::size_t n = q.size();
    std::vector<std::vector<double>> found;
    for (unsigned mask = 0; mask < (1u << n); ++mask) {
        std::vector<std::size_t> set;
        for (std::size_t i = 0; i < n; ++i)
            if (mask & (1u << i)) set.push_back(i);
        const std::size_t k = set.size();
        std::vector<double> a(k * k), b(k);
        for (std::size_t r = 0; r < k; ++r) {
            for (std::size_t c = 0; c < k; ++c) a[r * k + c] = m[set[r] * n + set[c]];
            b[r] = -q[set[r]];
        }
        bool singular = false;
        for (std::size_t c = 0; c < k && !singular; ++c) {
            std::size_t p = c;
            for (std::size_t r = c + 1; r < k; ++r)
                if (std::abs(a[r * k + c]) > std::abs(a[p * k + c])) p = r;
            if (std::abs(a[p * k + c]) < 1e-9) {
                singular = true;
                break;
            }
            for (std::size_t j = 0; j < k; ++j) std::swap(a[p * k + j], a[c * k + j]);
            std::swap(b[p], b[c]);
            for (std::size_t r = c + 1; r < k; ++r) {
                const double f = a[r * k + c] / a[c * k + c];
                for (std::size_t j = c; j < k; ++j) a[r * k + j] -= f * a[c * k + j];
                b[r] -= f * b[c];
            }
        }
        if (singular) continue;
        for (std::size_t c = k; c-- > 0;) {
            double s = b[c];
            for (std::size_t j = c + 1; j < k; ++j) s -= a[c * k + j] * b[j];
            b[c] = s / a[c * k + c];
        }
        std::vector<double> z(n, 0.0);
        for (std::size_t r = 0; r < k; ++r) z[set[r]] = b[r];
        bool ok = true;
        for (std::size_t i = 0; i < n && ok; ++i) {
            double w = q[i];
            for (std::size_t j = 0; j < n; ++j) w += m[i * n + j] * z[j];
            ok = z[i] >= -tolerance && w >= -tolerance;
        }
        if (ok) found.push_back(z);
    }
    return found;
}

std::vector<double> slackOf(const Matrix& m, const std::vector<double>& q,
                            const std::vector<double>& z) {
    std::vector<double> w = q;
    for (std::size_t i = 0; i < q.size(); ++i)
        for (std::size_t j = 0; j < q.size(); ++j) w[i] += m[i * q.size() + j] * z[j];
    return w;
}

// z >= 0, w >= 0 and |z_i w_i| within `tolerance`, w recomputed here.
void expectComplementary(const Matrix& m, const std::vector<double>& q, const LemkeSolution& s,
                         double tolerance) {
    const std::vector<double> w = slackOf(m, q, s.z);
    for (std::size_t i = 0; i < q.size(); ++i) {
        EXPECT_GE(s.z[i], 0.0) << "z[" << i << "]";
        EXPECT_GE(w[i], -tolerance) << "w[" << i << "]";
        EXPECT_LE(std::abs(s.z[i] * w[i]), tolerance) << "z[" << i << "] w[" << i << "]";
        EXPECT_NEAR(w[i], s.w[i], tolerance) << "reported w[" << i << "]";
    }
}

// M = G G^T with G n x rank: positive semidefinite, singular when rank < n.
Matrix randomPsd(std::size_t n, std::size_t rank, std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    Matrix gm(n * rank);
    for (double& v : gm) v = g(rng);
    Matrix m(n * n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t k = 0; k < rank; ++k) m[i * n + j] += gm[i * rank + k] * gm[j * rank + k];
    return m;
}

// For a positive semidefinite M every solution has the same w, so Lemke's w must equal the
// brute force's; for a P-matrix z itself is unique.
void checkAgainstBruteForce(const Matrix& m, const std::vector<double>& q, bool uniqueZ) {
    Result<LemkeSolution> s = solveLemke(m, q);
    const std::vector<std::vector<double>> all = bruteForceSolutions(m, q, 1e-9);
    ASSERT_FALSE(all.empty()) << "brute force found no solution";
    ASSERT_TRUE(s.ok()) << s.error().describe();
    expectComplementary(m, q, *s, 1e-6);
    const std::vector<double> w = slackOf(m, q, s->z), wRef = slackOf(m, q, all.front());
    for (std::size_t i = 0; i < q.size(); ++i) {
        EXPECT_NEAR(w[i], wRef[i], 1e-6) << "w[" << i << "]";
        if (uniqueZ) {
            EXPECT_NEAR(s->z[i], all.front()[i], 1e-6) << "z[" << i << "]";
        }
    }
}

TEST(Lemke, QAtLeastZeroIsSolvedByZero) {
    const Matrix m = {2, 1, 1, 2};
    Result<LemkeSolution> s = solveLemke(m, std::vector<double>{1.0, 0.0});
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->pivots, 0);
    EXPECT_EQ(s->z, (std::vector<double>{0.0, 0.0}));
}

TEST(Lemke, SolvesATwoByTwoByHand) {
    // z = M^-1 (-q) = (1, 1) for M = [[2, 1], [1, 2]], q = (-3, -3); w = 0.
    const Matrix m = {2, 1, 1, 2};
    Result<LemkeSolution> s = solveLemke(m, std::vector<double>{-3.0, -3.0});
    ASSERT_TRUE(s.ok()) << s.error().describe();
    EXPECT_NEAR(s->z[0], 1.0, 1e-12);
    EXPECT_NEAR(s->z[1], 1.0, 1e-12);
    EXPECT_NEAR(s->w[0], 0.0, 1e-12);
}

TEST(Lemke, MatchesBruteForceOnRandomPositiveDefiniteProblems) {
    std::mt19937 rng(11);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const std::size_t n = 1 + std::size_t(trial % 8);
        const Matrix m = randomPsd(n, n + 1, rng);
        std::vector<double> q(n);
        for (double& v : q) v = g(rng);
        SCOPED_TRACE("trial " + std::to_string(trial));
        checkAgainstBruteForce(m, q, true);
    }
}

TEST(Lemke, MatchesBruteForceOnSingularPositiveSemidefiniteProblems) {
    // Rank-deficient M, as four contact points under one box give; q = M y - s with y, s >= 0
    // makes each problem solvable (z = y is feasible).
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const std::size_t n = 2 + std::size_t(trial % 7);
        const Matrix m = randomPsd(n, 1 + std::size_t(trial % 3), rng);
        std::vector<double> y(n), q(n);
        for (double& v : y) v = u(rng) < 0.5 ? 0.0 : u(rng);
        q = slackOf(m, std::vector<double>(n, 0.0), y);
        for (double& v : q) v = -v + (u(rng) < 0.5 ? 0.0 : u(rng));
        SCOPED_TRACE("trial " + std::to_string(trial));
        checkAgainstBruteForce(m, q, false);
    }
}

TEST(Lemke, MatchesBruteForceOnDegenerateProblems) {
    // Repeated rows and columns, zeros and ties in q: every ratio test ties.
    std::mt19937 rng(13);
    for (int trial = 0; trial < 100; ++trial) {
        const std::size_t n = 3 + std::size_t(trial % 6);
        Matrix g(n * 2);
        for (std::size_t i = 0; i < n; ++i) {
            g[i * 2] = 1.0;
            g[i * 2 + 1] = double(int(i % 2) * 2 - 1) * 0.5;
        }
        Matrix m(n * n, 0.0);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                m[i * n + j] = g[i * 2] * g[j * 2] + g[i * 2 + 1] * g[j * 2 + 1];
        std::vector<double> q(n);
        for (std::size_t i = 0; i < n; ++i) q[i] = (trial % 3 == 0 && i == 0) ? 0.0 : -1.0;
        std::shuffle(q.begin(), q.end(), rng);
        SCOPED_TRACE("trial " + std::to_string(trial));
        checkAgainstBruteForce(m, q, false);
    }
}

TEST(Lemke, MatchesBruteForceOnNonsymmetricPMatrices) {
    // Strictly diagonally dominant with a positive diagonal: a P-matrix, so z is unique.
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 100; ++trial) {
        const std::size_t n = 1 + std::size_t(trial % 8);
        Matrix m(n * n);
        for (std::size_t i = 0; i < n; ++i) {
            double off = 0.0;
            for (std::size_t j = 0; j < n; ++j)
                if (i != j) off += std::abs(m[i * n + j] = u(rng));
            m[i * n + i] = off + 0.1 + std::abs(u(rng));
        }
        std::vector<double> q(n);
        for (double& v : q) v = u(rng);
        SCOPED_TRACE("trial " + std::to_string(trial));
        checkAgainstBruteForce(m, q, true);
    }
}

TEST(Lemke, SolvesAHundredRowsToComplementarity) {
    std::mt19937 rng(15);
    std::normal_distribution<double> g(0.0, 1.0);
    const std::size_t n = 100;
    const Matrix m = randomPsd(n, 60, rng);
    std::vector<double> y(n), q(n);
    for (double& v : y) v = std::abs(g(rng));
    q = slackOf(m, std::vector<double>(n, 0.0), y);
    for (std::size_t i = 0; i < n; ++i) q[i] = -q[i] + (i % 3 == 0 ? std::abs(g(rng)) : 0.0);
    Result<LemkeSolution> s = solveLemke(m, q);
    ASSERT_TRUE(s.ok()) << s.error().describe();
    expectComplementary(m, q, *s, 1e-6);
    EXPECT_LT(lcpNaturalResidual(m, q, s->z), 1e-8);
}

TEST(Lemke, AnInfeasibleProblemEndsOnARay) {
    // w_0 = -1 whatever z is: no solution.
    const Matrix m = {0, 0, 0, 1};
    Result<LemkeSolution> s = solveLemke(m, std::vector<double>{-1.0, 1.0});
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().kind, ErrorKind::Numerical);
    EXPECT_NE(s.error().message.find("secondary ray"), std::string::npos) << s.error().message;
}

TEST(Lemke, RefusesMismatchedAndOversizedProblems) {
    Result<LemkeSolution> bad = solveLemke(std::vector<double>(3, 1.0), std::vector<double>(2, -1.0));
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().kind, ErrorKind::BadInput);
    const std::size_t n = kLemkeMaxRows + 1;
    Result<LemkeSolution> big = solveLemke(std::vector<double>(n * n, 0.0), std::vector<double>(n, -1.0));
    ASSERT_FALSE(big.ok());
    EXPECT_EQ(big.error().kind, ErrorKind::BadInput);
    EXPECT_NE(big.error().message.find("at most 600"), std::string::npos) << big.error().message;
}

} // namespace
} // namespace rubble
