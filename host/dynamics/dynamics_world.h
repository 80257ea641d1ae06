// host/dynamics/dynamics_world.h: CPU stages 5 and 6 on a whole world (contact and joint rows,
// the velocity solve), the position corrections after stage 7, and islands and sleeping.
#pragma once

#include <vector>

#include "host/collision/contact.h"
#include "host/dynamics/contact_rows.h"
#include "host/dynamics/islands.h"
#include "host/dynamics/joint_positions.h"
#include "host/dynamics/joints.h"
#include "host/dynamics/solver_bodies.h"

namespace rubble {

struct WorldState;

/// Newton steps of the joint position correction per step (it stops once every joint holds).
inline constexpr int kJointPositionIterations = 20;

/// What the solver keeps between steps (impulses for warm starting, joints, sleep timers) and
/// the buffers it reuses. Ordered containers only: the reference path is deterministic.
struct SolverCache {
    bool jointsBuilt = false;
    std::vector<Joint> joints;    ///< the scene's joints in body frames, with impulses
    JointGroups jointGroups;      ///< joints connected through moving bodies
    JointPositionScratch jointScratch;
    std::vector<ContactImpulse> impulses; ///< last step's contact impulses, in pair order
    std::vector<ContactImpulse> nextImpulses, impulseScratch;
    SolverBodies bodies;                ///< this step's solver view of the bodies
    ContactRows contacts;               ///< this step's contact rows
    std::vector<float> residuals;       ///< largest |impulse change| of each sweep, N s
    bool pushed = false;                ///< the split position pass ran this step
    JointPositionReport jointPositions; ///< the last position correction
    SleepState sleep;
    std::vector<float> radii; ///< each body's bounding radius, m (for sleeping)
    SleepReport lastSleep;
};

/// Stage buildContactRows. reads: manifolds, poses, masses, materials, joints, solver cache
/// writes: constraint rows
void runBuildContactRows(WorldState& s);

/// Stage solve: PGS, then the split position pass. reads: rows   writes: velocities, impulses,
/// residuals (every sweep's), stats.solverResidual (the last sweep's)
void runSolveVelocities(WorldState& s);

/// After integratePositions: the contacts' split position pass moves the bodies, then the
/// joints are projected onto their constraints. writes: poses, velocities
void runSolvePositions(WorldState& s);

/// Islands and sleeping. reads: velocities, manifolds, joints, shapes
/// writes: masses[i].flags, velocities and momenta of bodies put to sleep
void runUpdateSleep(WorldState& s);

} // namespace rubble
