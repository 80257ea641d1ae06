// host/dynamics/lcp_convergence.h: the solvers side by side on one frozen contact set: the
// dense problem they all solve, each solver's impulses after every iteration, and the residual
// and complementarity error of an iterate (docs/solvers.md). `rubble solvers` prints them.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "host/dynamics/jacobi.h"
#include "host/dynamics/lcp_jacobi.h"
#include "host/dynamics/lemke.h"
#include "rubble/options.h"

namespace rubble {

/// One step's contact points and the bodies as that step's solve sees them.
struct FrozenContacts {
    std::int64_t step = 0;                         ///< the step (1-based) it was taken from
    std::vector<shared::ParticleContact> contacts; ///< points, normals (a to b), depths
    std::vector<shared::BodyPose> poses;
    std::vector<shared::BodyVelocity> velocities; ///< before the solve
    std::vector<shared::BodyMass> masses;
    std::vector<shared::float4> surfaces; ///< per body: friction, restitution
    SolverOptions solver;                 ///< the run's (iterations, relaxation)
    shared::SolverParams params{};        ///< the rows' settings, as the run's (solverParams)
};

/// The problem every solver is measured on: the jacobi solver's rows of the set, started from
/// zero (no warm start), and the dense w = A lambda + b built from them (one row per contact
/// when no contact has friction, else three).
struct FrozenProblem {
    FrozenContacts set;
    JacobiState jacobi;
    DenseLcp dense;
};

/// Builds the rows and the dense problem of a contact set. Errors: NotSupported when the dense
/// problem would have more than kLcpMaxRows rows.
Result<FrozenProblem> freezeProblem(FrozenContacts set);

/// How far an iterate lambda is from solving the problem (w = A lambda + b, D_ii = A_ii):
/// residual = max over rows of |D_ii (lambda_i - proj_i(lambda_i - w_i / D_ii))|, m/s, where
/// proj_i clamps a normal impulse to >= 0 and a friction impulse to +-mu times its contact's
/// normal impulse; for a normal row it is |min(D_ii lambda_i, w_i)|, the natural residual of the
/// LCP in velocity units. complementarity = sum over normal rows of |lambda_i w_i|, N m.
/// velocityError = max over normal rows of |w_i - w*_i| against Lemke's w* (unique for a
/// positive semidefinite A, unlike lambda), m/s, when a reference is given.
struct IterateErrors {
    double residual = 0;
    double complementarity = 0;
    std::optional<double> velocityError;
};
IterateErrors measureIterate(const DenseLcp& p, std::span<const float> lambda,
                             std::span<const double> referenceW = {});
IterateErrors measureIterate(const DenseLcp& p, std::span<const double> lambda,
                             std::span<const double> referenceW = {});

/// lambda after each of `iterations` sweeps (row stride * contact + direction), from zero.
using Iterates = std::vector<std::vector<float>>;

/// Projected Gauss-Seidel on A: each contact in order, its normal row then its friction rows,
/// lambda_i <- proj_i(lambda_i - omega w_i / A_ii) with w_i from the latest lambda. This is the
/// sweep of sequential impulses (solvePgs) written on the Delassus matrix, without its row
/// reordering, warm start and position pass.
Iterates pgsIterates(const FrozenProblem& p, int iterations, float relaxation);

/// The jacobi solver (solveJacobiRows and gatherJacobi, split masses, over-relaxed).
Iterates jacobiIterates(const FrozenProblem& p, int iterations, float relaxation);

/// The lcp-jacobi solver's CPU twin (solveLcpJacobi).
Iterates lcpJacobiIterates(const FrozenProblem& p, int iterations, float relaxation);

/// The rows' impulses as a dense lambda of the problem's stride.
std::vector<float> denseLambda(std::span<const shared::ContactRow> rows, std::uint32_t stride);

/// Lemke's method on the problem. Errors: NotSupported when a contact has friction or there
/// are more than kLemkeMaxRows rows, Numerical when it finds no solution.
Result<LemkeSolution> lemkeOf(const FrozenProblem& p);

} // namespace rubble
