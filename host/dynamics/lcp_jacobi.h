// host/dynamics/lcp_jacobi.h: the dense contact solvers on the CPU: lcp-jacobi (projected Jacobi
// on the Delassus matrix, twin of kernels/lcp_jacobi.cl with the math of rubble/shared/lcp.h)
// and lemke (exact pivoting, host/dynamics/lemke.h) on the same dense problem, built from the
// rows of the jacobi solver.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/core/step_params.h"
#include "rubble/shared/lcp.h"

namespace rubble {

/// One step's dense problem w = A lambda + b over the contact rows: `stride` rows per contact
/// (1: the normal only, when no contact can have friction; 3: normal and two tangents), row
/// stride * c + k for direction k of contact c.
struct DenseLcp {
    std::uint32_t contacts = 0;
    std::uint32_t stride = 1;
    std::vector<shared::LcpRow> rows; ///< Jacobian and M^-1 J^T of each row
    std::vector<float> matrix;        ///< A = J M^-1 J^T, row-major, (m/s)/(N s)
    std::vector<float> rhs;           ///< b = J v0 + bias, m/s
    std::vector<float> inverseScale;  ///< 1 / D_i with D_i = sum_j |A_ij| (0 for an empty row)
    std::vector<float> friction;      ///< per contact, Coulomb coefficient
    std::vector<float> lambda;        ///< impulses, N s
    std::vector<float> product;       ///< A lambda, m/s (scratch of the iteration)
    std::vector<float> residuals;     ///< largest |impulse change| of each iteration, N s

    std::uint32_t size() const { return contacts * stride; }
};

/// 1 when every row is frictionless, else 3.
std::uint32_t lcpStrideOfRows(std::span<const shared::ContactRow> rows);

/// Stage buildLcpRows: each contact row's `stride` dense rows, b from the velocities before the
/// solve, lambda from the rows' accumulated (warm-start) impulses, friction. A sleeping body
/// (RUBBLE_BODY_ASLEEP in its mass record's flags) takes part as a wall.
/// reads: rows, velocities, masses, poses   writes: p.rows, p.rhs, p.lambda, p.friction
void buildLcpRows(std::span<const shared::ContactRow> rows,
                  std::span<const shared::BodyVelocity> velocities,
                  std::span<const shared::BodyMass> masses,
                  std::span<const shared::BodyPose> poses, std::uint32_t stride, DenseLcp& p);

/// Stage assembleDelassus: A_ij = J_i M^-1 J_j^T. reads: p.rows   writes: p.matrix
void assembleDelassus(DenseLcp& p);

/// Stage scaleLcpRows: 1 / sum_j |A_ij| per row. reads: p.matrix   writes: p.inverseScale
void scaleLcpRows(DenseLcp& p);

/// Stage solveLcpJacobi: `iterations` times, product = A lambda (GEMV on the device), then
/// every contact's projectLcpItem from w = product + b (Jacobi: all from the same lambda).
/// reads: p   writes: p.lambda, p.product, p.residuals
void solveLcpJacobi(DenseLcp& p, int iterations, float relaxation);

/// Writes the dense impulses back into the contact rows (tangents 0 when stride is 1).
/// reads: p.lambda   writes: rows' lambda
void storeLcpImpulses(const DenseLcp& p, std::span<shared::ContactRow> rows);

/// The normal rows of the dense problem as an LCP for Lemke's method: M = A, q = b (stride 1
/// only), in double precision.
void lcpNormalProblem(const DenseLcp& p, std::vector<double>& m, std::vector<double>& q);

} // namespace rubble
