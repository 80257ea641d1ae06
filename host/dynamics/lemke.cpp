// host/dynamics/lemke.cpp: Lemke's complementary pivoting with a lexicographic ratio test, on an
// explicit basis inverse (Cottle, Pang and Stone 1992, algorithm 4.4.5 and section 4.9).
#include "host/dynamics/lemke.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace rubble {
namespace {

// Ratios closer than this, relative to their size, tie, and the rows of the basis inverse
// decide. Relative only: a resting contact's ratios can all be 1e-6 and differ in the 5th digit.
constexpr double kTieTolerance = 1e-11;

// A solution whose natural residual (scaled problem) exceeds this times max |q'| is refused.
constexpr double kAcceptedResidual = 1e-7;

bool ties(double x, double y) {
    return std::abs(x - y) <= kTieTolerance * std::max(std::abs(x), std::abs(y));
}

// The scaled system w - M' z - d z0 = q' in basic form: B^-1 and B^-1 q', and which variable is
// basic in each row. Variables: w_i is i, z_i is n + i, the artificial z0 is 2n.
struct Tableau {
    std::size_t n = 0;
    std::vector<double> inverse; // B^-1, row-major
    std::vector<double> value;   // B^-1 q': the basic variables' values
    std::vector<std::size_t> basic;
    std::vector<double> columnsOfM; // M'^T, row-major: column j of M' is row j here

    std::size_t artificial() const { return 2 * n; }
    const double* inverseRow(std::size_t i) const { return &inverse[i * n]; }
};

std::size_t complementOf(std::size_t v, std::size_t n) { return v < n ? v + n : v - n; }

// B^-1 times the column of variable v: e_v for w_v, -M'_{.j} for z_j, -d for z0.
void enteringColumn(const Tableau& t, std::size_t v, std::vector<double>& out) {
    const std::size_t n = t.n;
    out.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const double* row = t.inverseRow(i);
        if (v < n) {
            out[i] = row[v];
        } else if (v < 2 * n) {
            const double* column = &t.columnsOfM[(v - n) * n];
            double s = 0.0;
            for (std::size_t k = 0; k < n; ++k) s += row[k] * column[k];
            out[i] = -s;
        } else {
            double s = 0.0;
            for (std::size_t k = 0; k < n; ++k) s += row[k];
            out[i] = -s;
        }
    }
}

// A basic variable's value in the ratio test: round-off can leave a degenerate one slightly
// below zero, where it is zero (a negative ratio would look like the least).
double ratioOf(const Tableau& t, const std::vector<double>& column, std::size_t i) {
    return std::max(t.value[i], 0.0) / column[i];
}

// True when row i's (value, B^-1 row) / column is lexicographically smaller than row j's.
bool lexLess(const Tableau& t, const std::vector<double>& column, std::size_t i, std::size_t j) {
    const double ri = ratioOf(t, column, i), rj = ratioOf(t, column, j);
    if (!ties(ri, rj)) return ri < rj;
    const double* a = t.inverseRow(i);
    const double* b = t.inverseRow(j);
    for (std::size_t k = 0; k < t.n; ++k) {
        const double x = a[k] / column[i], y = b[k] / column[j];
        if (!ties(x, y)) return x < y;
    }
    return false; // equal rows cannot both be in a nonsingular basis inverse
}

// The blocking row for a variable entering with this column, or n when nothing blocks (a ray).
// When the artificial variable is among the rows that tie for the least ratio, it leaves.
std::size_t ratioTest(const Tableau& t, const std::vector<double>& column, double tolerance) {
    std::size_t best = t.n;
    for (std::size_t i = 0; i < t.n; ++i) {
        if (column[i] <= tolerance) continue;
        if (best == t.n || lexLess(t, column, i, best)) best = i;
    }
    if (best == t.n) return best;
    const double least = ratioOf(t, column, best);
    for (std::size_t i = 0; i < t.n; ++i)
        if (t.basic[i] == t.artificial() && column[i] > tolerance &&
            ties(ratioOf(t, column, i), least))
            return i;
    return best;
}

void pivot(Tableau& t, const std::vector<double>& column, std::size_t r, std::size_t entering) {
    const std::size_t n = t.n;
    const double p = column[r];
    double* pivotRow = &t.inverse[r * n];
    for (std::size_t k = 0; k < n; ++k) pivotRow[k] /= p;
    t.value[r] /= p;
    for (std::size_t i = 0; i < n; ++i) {
        const double f = column[i];
        if (i == r || f == 0.0) continue;
        double* row = &t.inverse[i * n];
        for (std::size_t k = 0; k < n; ++k) row[k] -= f * pivotRow[k];
        t.value[i] -= f * t.value[r];
    }
    t.basic[r] = entering;
}

// Solves the k x k system a x = b in place by Gaussian elimination with partial pivoting;
// false when a pivot is negligible against the matrix's largest entry.
bool solveDense(std::vector<double>& a, std::vector<double>& b, std::size_t k) {
    double largest = 0.0;
    for (double v : a) largest = std::max(largest, std::abs(v));
    const double tiny = 1e-13 * std::max(largest, 1e-300);
    for (std::size_t c = 0; c < k; ++c) {
        std::size_t p = c;
        for (std::size_t r = c + 1; r < k; ++r)
            if (std::abs(a[r * k + c]) > std::abs(a[p * k + c])) p = r;
        if (std::abs(a[p * k + c]) <= tiny) return false;
        if (p != c) {
            for (std::size_t j = 0; j < k; ++j) std::swap(a[p * k + j], a[c * k + j]);
            std::swap(b[p], b[c]);
        }
        for (std::size_t r = c + 1; r < k; ++r) {
            const double f = a[r * k + c] / a[c * k + c];
            if (f == 0.0) continue;
            for (std::size_t j = c; j < k; ++j) a[r * k + j] -= f * a[c * k + j];
            b[r] -= f * b[c];
        }
    }
    for (std::size_t c = k; c-- > 0;) {
        double s = b[c];
        for (std::size_t j = c + 1; j < k; ++j) s -= a[c * k + j] * b[j];
        b[c] = s / a[c * k + c];
    }
    return true;
}

// w = M z + q.
std::vector<double> slack(std::span<const double> m, std::span<const double> q,
                          std::span<const double> z) {
    const std::size_t n = q.size();
    std::vector<double> w(q.begin(), q.end());
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) w[i] += m[i * n + j] * z[j];
    return w;
}

// The final basis's z solved directly: M'_aa z_a = -q'_a over the basic z's. Kept when it is
// still a solution (round-off aside), which it is unless the basis is nearly singular.
void polish(std::span<const double> scaled, std::span<const double> q, std::vector<double>& z) {
    const std::size_t n = q.size();
    std::vector<std::size_t> active;
    for (std::size_t i = 0; i < n; ++i)
        if (z[i] > 0.0) active.push_back(i);
    const std::size_t k = active.size();
    if (k == 0) return;
    std::vector<double> a(k * k), b(k);
    for (std::size_t r = 0; r < k; ++r) {
        for (std::size_t c = 0; c < k; ++c) a[r * k + c] = scaled[active[r] * n + active[c]];
        b[r] = -q[active[r]];
    }
    if (!solveDense(a, b, k)) return;
    std::vector<double> candidate(n, 0.0);
    for (std::size_t r = 0; r < k; ++r) candidate[active[r]] = b[r];
    const std::vector<double> w = slack(scaled, q, candidate);
    double scale = 1.0;
    for (double v : q) scale = std::max(scale, std::abs(v));
    const double tolerance = 1e-9 * scale;
    for (std::size_t i = 0; i < n; ++i)
        if (candidate[i] < -tolerance || w[i] < -tolerance) return;
    for (double& v : candidate) v = std::max(v, 0.0);
    z = std::move(candidate);
}

} // namespace

Result<LemkeSolution> solveLemke(std::span<const double> m, std::span<const double> q,
                                 const LemkeOptions& options) {
    const std::size_t n = q.size();
    if (m.size() != n * n)
        return makeError(ErrorKind::BadInput, "lemke",
                         "M has " + std::to_string(m.size()) + " entries; q has " +
                             std::to_string(n) + " rows, so M needs " + std::to_string(n * n));
    if (n > kLemkeMaxRows)
        return makeError(ErrorKind::BadInput, "lemke",
                         "the problem has " + std::to_string(n) + " rows; Lemke's method here "
                         "takes at most " + std::to_string(kLemkeMaxRows));

    // Symmetric scaling to a unit diagonal where the diagonal is positive.
    std::vector<double> s(n, 1.0);
    for (std::size_t i = 0; i < n; ++i)
        if (m[i * n + i] > 0.0) s[i] = 1.0 / std::sqrt(m[i * n + i]);
    std::vector<double> scaled(n * n), scaledQ(n);
    for (std::size_t i = 0; i < n; ++i) {
        scaledQ[i] = s[i] * q[i];
        for (std::size_t j = 0; j < n; ++j) scaled[i * n + j] = s[i] * m[i * n + j] * s[j];
    }

    LemkeSolution out;
    out.z.assign(n, 0.0);
    const bool trivial = std::all_of(scaledQ.begin(), scaledQ.end(), [](double v) { return v >= 0.0; });
    if (!trivial) {
        Tableau t;
        t.n = n;
        t.inverse.assign(n * n, 0.0);
        for (std::size_t i = 0; i < n; ++i) t.inverse[i * n + i] = 1.0;
        t.value = scaledQ;
        t.basic.resize(n);
        for (std::size_t i = 0; i < n; ++i) t.basic[i] = i;
        t.columnsOfM.resize(n * n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) t.columnsOfM[j * n + i] = scaled[i * n + j];

        // z0 enters at the most negative q'_i; among ties the last row, which leaves every
        // other row lexicographically positive.
        std::size_t r = 0;
        for (std::size_t i = 1; i < n; ++i)
            if (t.value[i] < t.value[r] || ties(t.value[i], t.value[r])) r = i;
        std::vector<double> column;
        enteringColumn(t, t.artificial(), column);
        pivot(t, column, r, t.artificial());
        out.pivots = 1;
        std::size_t driving = complementOf(r, n);

        const int limit = options.maxPivots > 0 ? options.maxPivots : int(50 * n + 100);
        for (;;) {
            if (out.pivots >= limit)
                return makeError(ErrorKind::Numerical, "lemke",
                                 "no solution after " + std::to_string(out.pivots) +
                                     " pivots (the pivot limit)");
            enteringColumn(t, driving, column);
            r = ratioTest(t, column, options.pivotTolerance);
            if (r == n)
                return makeError(ErrorKind::Numerical, "lemke",
                                 "the method ended on a secondary ray after " +
                                     std::to_string(out.pivots) +
                                     " pivots: the problem has no solution (for contacts: no "
                                     "impulses >= 0 reach every asked separation speed)");
            const std::size_t leaving = t.basic[r];
            pivot(t, column, r, driving);
            ++out.pivots;
            if (leaving == t.artificial()) break;
            driving = complementOf(leaving, n);
        }
        for (std::size_t i = 0; i < n; ++i)
            if (t.basic[i] >= n && t.basic[i] < 2 * n)
                out.z[t.basic[i] - n] = std::max(t.value[i], 0.0);
        polish(scaled, scaledQ, out.z);
        // The pivots are exact in exact arithmetic; a basis that round-off broke shows here.
        double scale = 0.0;
        for (double v : scaledQ) scale = std::max(scale, std::abs(v));
        const double residual = lcpNaturalResidual(scaled, scaledQ, out.z);
        if (residual > kAcceptedResidual * scale)
            return makeError(ErrorKind::Numerical, "lemke",
                             "round-off: the final basis leaves a residual of " +
                                 std::to_string(residual) + " against |q| up to " +
                                 std::to_string(scale) + " (after " +
                                 std::to_string(out.pivots) + " pivots)");
    }
    for (std::size_t i = 0; i < n; ++i) out.z[i] *= s[i];
    out.w = slack(m, q, out.z);
    return out;
}

double lcpNaturalResidual(std::span<const double> m, std::span<const double> q,
                          std::span<const double> z) {
    const std::vector<double> w = slack(m, q, z);
    double r = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) r = std::max(r, std::abs(std::min(z[i], w[i])));
    return r;
}

} // namespace rubble
