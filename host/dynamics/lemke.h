// host/dynamics/lemke.h: Lemke's complementary pivoting for the linear complementarity problem
// w = M z + q, w >= 0, z >= 0, w^T z = 0 (Cottle, Pang and Stone, "The Linear Complementarity
// Problem", 1992, section 4.4), the exact solver of small frictionless contact sets.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "rubble/error.h"

namespace rubble {

/// Lemke's method is dense and cubic: larger contact sets belong to the iterative solvers.
inline constexpr std::size_t kLemkeMaxRows = 600;

struct LemkeOptions {
    /// Pivots before giving up; 0: 50 n + 100 (the lexicographic rule cannot cycle, so a
    /// solvable problem ends far sooner).
    int maxPivots = 0;
    /// Entries of a pivot column at or below this (after scaling, see solveLemke) cannot block.
    double pivotTolerance = 1e-11;
};

/// A solution of the LCP.
struct LemkeSolution {
    std::vector<double> z;    ///< >= 0
    std::vector<double> w;    ///< M z + q, >= 0 up to round-off
    int pivots = 0;           ///< pivots taken (0 when q >= 0)
};

/// Solves w = M z + q, w >= 0, z >= 0, w^T z = 0 for a row-major n x n M (any matrix Lemke's
/// method processes: positive semidefinite, P, copositive-plus). The problem is first scaled
/// symmetrically so that diag(M) = 1 where it is positive (z = S z', M' = S M S, q' = S q), which
/// makes the covering vector d = (1, ..., 1) weigh every row alike. Ties in the ratio test are
/// broken lexicographically on the rows of the basis inverse (Cottle et al., 4.9), so the method
/// cannot cycle on degenerate problems; when the artificial variable z0 ties, it leaves. The
/// final complementary basis is solved once more directly, which removes the round-off the
/// pivots accumulated.
/// Errors: BadInput for sizes that do not match or n > kLemkeMaxRows; Numerical when the method
/// ends on a secondary ray (for a positive semidefinite M: the problem has no solution) or runs
/// out of pivots.
Result<LemkeSolution> solveLemke(std::span<const double> m, std::span<const double> q,
                                 const LemkeOptions& options = {});

/// Largest violation of the LCP by (z, w = M z + q): max over i of |min(z_i, w_i)|.
double lcpNaturalResidual(std::span<const double> m, std::span<const double> q,
                          std::span<const double> z);

} // namespace rubble
