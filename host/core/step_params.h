// host/core/step_params.h: the settings of one step, built once per step from the simulation
// options and handed to every stage (CPU and device), and the solver settings derived from the
// options and materials that the CPU twins and the device dispatch share.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rubble/options.h"
#include "rubble/scene.h"
#include "rubble/shared/contact_row.h"

namespace rubble {

/// What a stage may read of the options, for the step being taken.
struct StepParams {
    std::int64_t step = 0; ///< steps taken before this one
    double time = 0.0;     ///< s, at the start of the step
    float dt = 1.0f / 60.0f;
    shared::float4 gravity{}; ///< m/s^2, world frame
    Integrator integrator = Integrator::Symplectic;
    CollisionMethod collision = CollisionMethod::Sat;
    float particleSpacing = 0.1f;     ///< m
    bool continuous = true;           ///< contact margins widened by the motion (SatCollision)
    bool recycleContacts = false;     ///< hull and level pairs that moved little keep manifolds
    SolverOptions solver;             ///< the scene's solver block as given
    shared::SolverParams rows{};      ///< the contact rows of the jacobi family (solverParams)
    float jacobiRelaxation = 1.0f;    ///< jacobiRelaxation(solver)
    float lcpJacobiRelaxation = 1.0f; ///< lcpJacobiRelaxation(solver)
    bool sleep = true;                ///< still bodies may go to sleep (SimulationOptions::sleep)

    bool symplectic() const { return integrator == Integrator::Symplectic; }
};

/// The parameters of the step after `stepsTaken` steps.
StepParams makeStepParams(const SimulationOptions& o, std::int64_t stepsTaken);

/// Over-relaxation of every row update of the Jacobi solver, on top of the scene's relaxation.
/// Mass splitting alone converges but slowly (each row moves 1/n of its way when its bodies
/// have n rows): at 10 iterations a resting stack then jitters, which 1.5 brings to rest, while
/// larger values start to overshoot in piles. Successive over-relaxation of a projected Jacobi
/// sweep converges for 0 < omega < 2 on the split system (Tonge et al. 2012, section 4).
inline constexpr float kJacobiOverRelaxation = 1.5f;

/// The relaxation the Jacobi solver uses: the scene's times kJacobiOverRelaxation.
float jacobiRelaxation(const SolverOptions& o);

/// Over-relaxation of lcp-jacobi on top of the scene's relaxation. D is the row sum of |A|, so
/// D - A/2 is positive definite and any omega in (0, 2) converges (with D = diag(A) the
/// iteration diverges on a resting stack); a larger omega converges faster on the frozen
/// stacks of docs/solvers.md, and 1.8 keeps a margin below 2.
inline constexpr float kLcpJacobiOverRelaxation = 1.8f;

/// The relaxation lcp-jacobi uses: the scene's times kLcpJacobiOverRelaxation.
float lcpJacobiRelaxation(const SolverOptions& o);

/// The dense problem grows as rows^2: lcp-jacobi is for small systems (64 MiB of A at most).
inline constexpr std::uint32_t kLcpMaxRows = 4096;

/// The contact rows' settings of the jacobi-family solvers. With particle contacts the slop is
/// at least a tenth of the particle spacing (shared::particleSlopItem).
shared::SolverParams solverParams(const SimulationOptions& o);

/// Per body: friction in x, restitution in y (its material). reads: materials, materialOf
std::vector<shared::float4> bodySurfaces(std::span<const MaterialDesc> materials,
                                         std::span<const std::uint32_t> materialOf);

/// Rows per contact of the dense problem: 1 when no two bodies of which one is dynamic both have
/// friction (every contact is then frictionless and the tangent rows would stay 0), else 3.
/// reads: surfaces (x = friction), masses
std::uint32_t lcpStride(std::span<const shared::float4> surfaces,
                        std::span<const shared::BodyMass> masses);

} // namespace rubble
