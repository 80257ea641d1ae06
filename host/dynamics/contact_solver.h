// host/dynamics/contact_solver.h: the solver stages of the CPU step (buildContactRows, solve,
// the position corrections after integratePositions, and sleeping) behind one interface, so that
// a world picks its solver once, when it is built: PgsSolver (host/dynamics/pgs_solver.h, the
// reference), SoftStepSolver (host/dynamics/soft_step_solver.h) or the CPU twins of the device's
// solvers (host/dynamics/jacobi_solver.h: jacobi, lcp-jacobi, lemke).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "host/collision/collision_stage.h"
#include "host/core/bodies.h"
#include "host/core/step_params.h"
#include "host/dynamics/joints.h"
#include "rubble/error.h"
#include "rubble/scene.h"

namespace rubble {

/// What the solver stages read of the world besides the body arrays and the contacts. It
/// changes only when bodies are added or removed (ContactSolver::bodiesChanged).
struct SolverScene {
    std::span<const Shape> shapes; ///< bounding radii, for sleeping
    std::span<const MaterialDesc> materials;
    std::span<const shared::float4> surfaces; ///< per body: friction, restitution (bodySurfaces)
    std::span<const JointDesc> joints;        ///< the scene's, by body index
    std::span<const BodyPair> joined;         ///< the joints' body pairs, (min, max), sorted
    std::span<const std::string> names;       ///< per body, for errors
};

/// No body: the new index of a removed body in ContactSolver::bodiesChanged.
inline constexpr std::uint32_t kRemovedBody = 0xffffffffu;

/// A contact solver's stages, with what they keep between steps.
class ContactSolver {
  public:
    virtual ~ContactSolver() = default;

    /// The form of contacts buildRows reads.
    virtual ContactForm reads() const = 0;
    /// Stage wake, after narrowPhase: the sleeping bodies that this step's contacts, joints or
    /// impulses from outside touch wake before the rows, so that their mass takes part in the
    /// solve. `approach` as in buildRows. Returns true when the bodies it woke have pairs that
    /// were not collided while they slept: the caller runs broadPhase and narrowPhase again and
    /// calls wake once more. reads: contacts, bodies, approach, scene
    /// writes: masses (flags), the solver's sleep state
    [[nodiscard]] virtual bool wake(const SolverScene& scene, Bodies bodies,
                                    std::span<const shared::BodyVelocity> approach,
                                    const StepContacts& contacts, const StepParams& params) = 0;
    /// Stage buildContactRows. `approach` holds the bodies' velocities before this step's
    /// forces, which restitution measures the approach with (the velocities in `bodies` are
    /// after them). reads: contacts, bodies, approach, scene, params   writes: the rows
    virtual void buildRows(const SolverScene& scene, BodiesView bodies,
                           std::span<const shared::BodyVelocity> approach,
                           const StepContacts& contacts, const StepParams& params) = 0;
    /// Stage solve: the bodies' velocities from the rows, `before` holding them as they were
    /// before it. Errors: those of the dense solvers (a contact set they cannot take, no
    /// solution), naming the step. reads: rows, before   writes: velocities, impulses kept
    [[nodiscard]] virtual Status solve(const SolverScene& scene, Bodies bodies,
                                       std::span<const shared::BodyVelocity> before,
                                       const StepContacts& contacts, const StepParams& params) = 0;
    /// After integratePositions: position-level corrections. writes: poses, velocities
    virtual void solvePositions(const SolverScene& scene, Bodies bodies,
                                const StepParams& params) = 0;
    /// True when solve moves the bodies itself, in substeps (soft step): the step then leaves
    /// integratePositions out, and solvePositions puts the bodies where the substeps took them.
    virtual bool integratesPositions() const { return false; }
    /// Stage islands: sleeping and waking. Returns the bodies asleep after it.
    /// writes: masses (flags), velocities and momenta of bodies put to sleep
    virtual std::uint32_t sleep(const SolverScene& scene, Bodies bodies,
                                const StepContacts& contacts, const StepParams& params) = 0;
    /// The largest |impulse change| of each sweep of the last solve, N s (empty for a direct
    /// solver).
    virtual std::span<const float> residuals() const = 0;
    /// The scene's joints in the bodies' frames as the solver holds them (renumbered with the
    /// bodies), for the joint watch after the step; empty for a solver without joint rows and
    /// before the first step.
    virtual std::span<const Joint> joints() const { return {}; }
    /// Bodies were added or removed: body i is now newIndex[i] (kRemovedBody when it went).
    /// What is kept by body index (warm starts, sleep timers) is forgotten, joints renumbered.
    virtual void bodiesChanged(std::span<const std::uint32_t> newIndex, BodiesView bodies) = 0;
};

/// The stage object of a solver type.
std::unique_ptr<ContactSolver> makeContactSolver(SolverType type);

} // namespace rubble
