// host/dynamics/jacobi_solver.h: the solver stages of the CPU twins of the device's solvers:
// jacobi (host/dynamics/jacobi.h), and lcp-jacobi and lemke on the dense problem built from its
// rows (host/dynamics/lcp_jacobi.h, lemke.h); all three sleep as the device does
// (host/dynamics/sleep.h).
#pragma once

#include <vector>

#include "host/dynamics/contact_solver.h"
#include "host/dynamics/jacobi.h"
#include "host/dynamics/lcp_jacobi.h"
#include "host/dynamics/sleep.h"

namespace rubble {

/// The per-row projected Jacobi solver with mass splitting.
class JacobiSolver : public ContactSolver {
  public:
    ContactForm reads() const override { return ContactForm::Points; }
    /// Stage wakeTouched (the device's twin): its woken bodies' contacts come next step, so it
    /// never asks for the collision stages again (false).
    bool wake(const SolverScene& scene, Bodies bodies,
              std::span<const shared::BodyVelocity> approach, const StepContacts& contacts,
              const StepParams& params) override;
    /// Stage buildJacobiRows: the body lists, the warm start matched by contact key, a row per
    /// contact point, its approach measured with `approach`. reads: points, poses, approach,
    /// masses, surfaces
    void buildRows(const SolverScene& scene, BodiesView bodies,
                   std::span<const shared::BodyVelocity> approach, const StepContacts& contacts,
                   const StepParams& params) override;
    /// Stage solveJacobi; the impulses kept for the next step's warm start.
    Status solve(const SolverScene& scene, Bodies bodies,
                 std::span<const shared::BodyVelocity> before, const StepContacts& contacts,
                 const StepParams& params) override;
    /// No position pass: Baumgarte is in the rows.
    void solvePositions(const SolverScene&, Bodies, const StepParams&) override {}
    /// Stage sleepBodies on the rows of the solve.
    std::uint32_t sleep(const SolverScene& scene, Bodies bodies, const StepContacts& contacts,
                        const StepParams& params) override;
    std::span<const float> residuals() const override { return jacobi_.residuals; }
    void bodiesChanged(std::span<const std::uint32_t> newIndex, BodiesView bodies) override;

    const JacobiState& state() const { return jacobi_; }

  protected:
    /// The solve's impulses into the velocities, and kept for the next step's warm start.
    void finishSolve(Bodies bodies, std::span<const shared::BodyVelocity> before,
                     const StepContacts& contacts, const StepParams& params);

    JacobiState jacobi_;
    BodySleepState sleep_;
};

/// Projected Jacobi on the dense Delassus matrix of the jacobi solver's rows.
class LcpJacobiSolver final : public JacobiSolver {
  public:
    /// Errors: NotSupported when the dense problem would exceed kLcpMaxRows.
    Status solve(const SolverScene& scene, Bodies bodies,
                 std::span<const shared::BodyVelocity> before, const StepContacts& contacts,
                 const StepParams& params) override;
    std::span<const float> residuals() const override { return dense_.residuals; }

  private:
    DenseLcp dense_;
};

/// Lemke's exact pivoting on the frictionless dense problem.
class LemkeSolver final : public JacobiSolver {
  public:
    /// Errors: NotSupported when a contact has friction or there are more than kLemkeMaxRows
    /// rows; Numerical when Lemke's method finds no solution.
    Status solve(const SolverScene& scene, Bodies bodies,
                 std::span<const shared::BodyVelocity> before, const StepContacts& contacts,
                 const StepParams& params) override;
    std::span<const float> residuals() const override { return {}; }

  private:
    DenseLcp dense_;
};

} // namespace rubble
