// host/dynamics/jacobi.h: the per-row projected Jacobi contact solver on the CPU (OpenCL stage
// 5), twin of kernels/jacobi.cl with the math of rubble/shared/contact_row.h. Each iteration
// updates every row from the velocities of the last one, then gathers each body's rows into
// its velocity; mass splitting (Tonge, Benevolenski and Voroshilov, "Mass splitting for
// jitter-free parallel rigid body simulation", SIGGRAPH 2012) makes the gather converge.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rubble/shared/contact_row.h"
#include "rubble/shared/particle.h"

namespace rubble {

/// A contact's accumulated impulses kept for the next step, by its key: the two particles (or
/// SAT's body a and feature id) and body b.
struct WarmImpulse {
    std::uint32_t particleA = 0, featureB = 0, b = 0;
    shared::float4 lambda{};
    friend bool operator<(const WarmImpulse& x, const WarmImpulse& y) {
        if (x.particleA != y.particleA) return x.particleA < y.particleA;
        return x.featureB != y.featureB ? x.featureB < y.featureB : x.b < y.b;
    }
};

/// The rows of one step and each body's list of them.
struct JacobiState {
    std::vector<shared::ContactRow> rows;
    std::vector<std::uint32_t> bodyCount; ///< rows on each dynamic body (its mass split)
    std::vector<std::uint32_t> bodyStart; ///< first entry of each body in bodyList (n + 1)
    std::vector<std::uint32_t> bodyList;  ///< entries 2 row + side (0: body a, 1: body b)
    std::vector<float> residuals;         ///< largest |impulse change| of each iteration, N s
    std::vector<shared::float4> warm;  ///< per contact: last step's impulses, or zero
    std::vector<WarmImpulse> previous; ///< last step's impulses, sorted by key
};

/// Stage matchWarmStart: each contact's impulses of the last step when the same pair of
/// features touched then, else zero. reads: contacts, previous   writes: warm
void matchWarmStart(std::span<const shared::ParticleContact> contacts,
                    std::span<const WarmImpulse> previous, std::vector<shared::float4>& warm);

/// Keeps this step's impulses for the next one. reads: contacts, rows   writes: previous
void rememberImpulses(std::span<const shared::ParticleContact> contacts,
                      std::span<const shared::ContactRow> rows, std::vector<WarmImpulse>& previous);

/// Per-body lists of rows, in row order: counts, starts, entries 2 row + side. Static bodies
/// get no list. reads: contacts, masses   writes: bodyCount, bodyStart, bodyList
void buildBodyLists(std::span<const shared::ParticleContact> contacts,
                    std::span<const shared::BodyMass> masses, JacobiState& j);

/// Stage buildJacobiRows: a row per contact with split masses (each body's mass shared among
/// its rows), starting from `warm`; restitution measures the approach with `approach`, the
/// velocities before this step's forces. reads: contacts, poses, approach, masses, surfaces,
/// bodyCount, warm   writes: rows
void buildJacobiRows(std::span<const shared::ParticleContact> contacts,
                     std::span<const shared::BodyPose> poses,
                     std::span<const shared::BodyVelocity> approach,
                     std::span<const shared::BodyMass> masses,
                     std::span<const shared::float4> surfaces, shared::SolverParams params,
                     std::span<const shared::float4> warm, JacobiState& j);

/// One Jacobi iteration's row update: every row's new accumulated impulses from `velocities`.
/// Returns the largest |impulse change|. reads: rows, velocities   writes: rows (lambda)
float solveJacobiRows(std::span<shared::ContactRow> rows,
                      std::span<const shared::BodyVelocity> velocities, float relaxation);

/// Each dynamic body's velocity from the solve's start velocity and its rows' impulses:
/// v = v0 + M^-1 sum J^T lambda. reads: rows, lists, before, masses, poses   writes: velocities
void gatherJacobi(std::span<const shared::ContactRow> rows, const JacobiState& j,
                  std::span<const shared::BodyVelocity> before,
                  std::span<const shared::BodyMass> masses, std::span<const shared::BodyPose> poses,
                  std::span<shared::BodyVelocity> velocities);

/// Stage solveJacobi: `iterations` sweeps of solveJacobiRows then gatherJacobi, residuals kept.
/// reads: rows, before   writes: rows (lambda), velocities, j.residuals
void solveJacobi(JacobiState& j, std::span<const shared::BodyVelocity> before,
                 std::span<const shared::BodyMass> masses, std::span<const shared::BodyPose> poses,
                 std::span<shared::BodyVelocity> velocities, int iterations, float relaxation);

} // namespace rubble
