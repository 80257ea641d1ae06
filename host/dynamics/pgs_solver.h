// host/dynamics/pgs_solver.h: the solver stages of the CPU reference pipeline: contact and joint
// rows (host/dynamics/contact_rows.h, joints.h), projected Gauss-Seidel (pgs.h), the split
// position pass and the joint projection after integratePositions, and islands and sleeping
// (islands.h).
#pragma once

#include <vector>

#include "host/dynamics/contact_rows.h"
#include "host/dynamics/contact_solver.h"
#include "host/dynamics/solver_islands.h"
#include "host/dynamics/joint_positions.h"
#include "host/dynamics/joints.h"
#include "host/dynamics/solver_bodies.h"
#include "rubble/shared/pgs_joint.h"

namespace rubble {

/// Newton steps of the joint position correction per step (it stops once every joint holds);
/// the device's projection takes as many sweeps.
inline constexpr int kJointPositionIterations = RUBBLE_JOINT_POSITION_ITERATIONS;

/// What the solver keeps between steps (impulses for warm starting, joints, sleep timers) and
/// the buffers it reuses. Ordered containers only: the reference path is deterministic.
struct SolverCache {
    bool jointsBuilt = false;
    std::vector<Joint> joints; ///< the scene's joints in body frames, with impulses
    JointGroups jointGroups;   ///< joints connected through moving bodies
    JointPositionScratch jointScratch;
    std::vector<ContactImpulse> impulses; ///< last step's contact impulses, in pair order
    std::vector<ContactImpulse> nextImpulses, impulseScratch;
    SolverBodies bodies;                ///< this step's solver view of the bodies
    ContactRows contacts;               ///< this step's contact rows
    std::vector<float> residuals;       ///< largest |impulse change| of each sweep, N s
    bool pushed = false;                ///< the split position pass ran this step
    JointPositionReport jointPositions; ///< the last position correction
    SolverIslands islands; ///< islands and sleep timers
};

/// Projected Gauss-Seidel with warm start, split impulses, joints and islands.
class PgsSolver final : public ContactSolver {
  public:
    ContactForm reads() const override { return ContactForm::Manifolds; }
    /// Islands touched by a restless body wake (wakeIslands), with their pairs collided again:
    /// true when it woke a body.
    bool wake(const SolverScene& scene, Bodies bodies,
              std::span<const shared::BodyVelocity> approach, const StepContacts& contacts,
              const StepParams& params) override;
    /// Contact rows from the manifolds, joint rows (the joints are put in body frames at the
    /// poses of the first step); bounces from the approach in `approach`. reads: manifolds,
    /// poses, velocities, approach, masses, materials, joints, the cache
    void buildRows(const SolverScene& scene, BodiesView bodies,
                   std::span<const shared::BodyVelocity> approach, const StepContacts& contacts,
                   const StepParams& params) override;
    /// PGS, then the split position pass; impulses kept for the next step's warm start.
    Status solve(const SolverScene& scene, Bodies bodies,
                 std::span<const shared::BodyVelocity> before, const StepContacts& contacts,
                 const StepParams& params) override;
    /// The contacts' split position pass moves the bodies out of each other, then the joints
    /// are projected onto their constraints.
    void solvePositions(const SolverScene& scene, Bodies bodies, const StepParams& params) override;
    /// Islands and sleeping (updateSleep). reads: manifolds, joints, velocities, shapes
    std::uint32_t sleep(const SolverScene& scene, Bodies bodies, const StepContacts& contacts,
                        const StepParams& params) override;
    std::span<const float> residuals() const override { return cache_.residuals; }
    std::span<const Joint> joints() const override {
        if (!cache_.jointsBuilt) return {};
        return cache_.joints;
    }
    void bodiesChanged(std::span<const std::uint32_t> newIndex, BodiesView bodies) override;

    const SolverCache& cache() const { return cache_; }

  private:
    SolverCache cache_;
};

} // namespace rubble
