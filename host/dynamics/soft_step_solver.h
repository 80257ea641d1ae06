// host/dynamics/soft_step_solver.h: the solver stages of the soft-step solver on the CPU: the
// contact rows of the reference (host/dynamics/contact_rows.h) with their soft-step points, joints,
// the substeps (soft_step.h), which move the bodies themselves, and islands and sleeping as PGS.
#pragma once

#include <vector>

#include "host/dynamics/contact_rows.h"
#include "host/dynamics/contact_solver.h"
#include "host/dynamics/joints.h"
#include "host/dynamics/soft_step.h"
#include "host/dynamics/solver_bodies.h"
#include "host/dynamics/solver_islands.h"

namespace rubble {

/// What the soft step keeps between steps (per-substep impulses for warm starting, joints, sleep
/// timers) and the buffers it reuses.
struct SoftStepCache {
    bool jointsBuilt = false;
    std::vector<Joint> joints; ///< the scene's joints in body frames, with impulses per substep
    std::vector<ContactImpulse> impulses; ///< last step's contact impulses per substep, pair order
    std::vector<ContactImpulse> nextImpulses, impulseScratch;
    SolverBodies bodies;
    ContactRows contacts;
    std::vector<SoftContactPoint> points;     ///< in the rows' order
    std::vector<SoftManifold> pointManifolds; ///< each manifold's points, manifold order
    std::vector<shared::BodyVelocity> start;  ///< velocities before the step's forces
    SoftPoses poses;                          ///< the bodies' poses through the substeps
    SoftPassRows packed;                      ///< the passes' packed rows and points
    std::vector<float> residuals;
    SolverIslands islands; ///< islands and sleep timers
};

/// Catto's soft step: substeps, soft contacts and joints, relax passes, restitution after.
class SoftStepSolver final : public ContactSolver {
  public:
    ContactForm reads() const override { return ContactForm::Manifolds; }
    bool wake(const SolverScene& scene, Bodies bodies,
              std::span<const shared::BodyVelocity> approach, const StepContacts& contacts,
              const StepParams& params) override;
    /// The reference's contact rows (effective masses, tangents, warm start by feature id) and
    /// each point's offsets, separation and approach speed; joints in body frames at the first
    /// step's poses. reads: manifolds, poses, velocities, approach, masses, materials, joints
    void buildRows(const SolverScene& scene, BodiesView bodies,
                   std::span<const shared::BodyVelocity> approach, const StepContacts& contacts,
                   const StepParams& params) override;
    /// The substeps (solveSoftStep): the velocities at the step's end; the poses are kept for
    /// solvePositions. `before` holds the velocities after the step's forces.
    Status solve(const SolverScene& scene, Bodies bodies,
                 std::span<const shared::BodyVelocity> before, const StepContacts& contacts,
                 const StepParams& params) override;
    /// The substeps' poses become the bodies' (the step leaves integratePositions out), and the
    /// velocities are derived from the momenta at them.
    void solvePositions(const SolverScene& scene, Bodies bodies, const StepParams& params) override;
    bool integratesPositions() const override { return true; }
    std::uint32_t sleep(const SolverScene& scene, Bodies bodies, const StepContacts& contacts,
                        const StepParams& params) override;
    std::span<const float> residuals() const override { return cache_.residuals; }
    std::span<const Joint> joints() const override {
        if (!cache_.jointsBuilt) return {};
        return cache_.joints;
    }
    void bodiesChanged(std::span<const std::uint32_t> newIndex, BodiesView bodies) override;

  private:
    SoftStepCache cache_;
};

} // namespace rubble
