// host/world/cpu_step.cpp: the CPU step as a list of stages, each timed. The collision and
// solver stages are the objects the world was built with (SAT or particles; PGS or a twin of
// the device's solvers): no stage is chosen here.
#include "host/world/cpu_step.h"

#include <algorithm>
#include <chrono>

#include "host/core/clock.h"
#include "host/core/integrate.h"
#include "host/core/step_params.h"
#include "host/dynamics/forces.h"
#include "host/world/step_stop.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// Adds the wall time of its scope to a StepStats field, in milliseconds.
class StageTimer {
  public:
    explicit StageTimer(double& total) : total_(total), start_(Clock::now()) {}
    ~StageTimer() { total_ += msSince(start_); }
    StageTimer(const StageTimer&) = delete;
    StageTimer& operator=(const StageTimer&) = delete;

  private:
    double& total_;
    Clock::time_point start_;
};

} // namespace

Status stepCpu(WorldState& s, StepStats& stats) {
    const StepParams p = makeStepParams(s.options, s.step);
    const Bodies bodies = s.bodies.view();
    const CollisionScene collisionScene = s.collisionScene();
    const SolverScene solverScene = s.solverScene();
    StepContacts& contacts = s.contacts;
    {
        StageTimer t(stats.applyForcesMs);
        applyDueExplosions(s.events, s.eventFired, p.time, bodies);
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.integrateVelocitiesMs);
        // The velocities before the forces: restitution's approach, explicit Euler's motion.
        integrateVelocities(bodies.momenta, bodies.forces, bodies.masses, bodies.poses,
                            bodies.velocities, s.velocitiesAtStart, p.gravity, p.dt);
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.broadPhaseMs);
        RUBBLE_TRY(s.collision->broadPhase(collisionScene, bodies, p, contacts));
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.narrowPhaseMs);
        RUBBLE_TRY(s.collision->narrowPhase(collisionScene, bodies, p, contacts));
    }
    // Sleeping bodies that this step's contacts, joints or impulses touch wake before the rows,
    // so that their mass takes part in the solve; pairs not collided while they slept are
    // collided now (each round wakes at least one body).
    for (;;) {
        bool collideAgain = false;
        {
            StageTimer t(stats.islandsMs);
            collideAgain = s.solver->wake(solverScene, bodies, s.velocitiesAtStart, contacts, p);
        }
        if (!collideAgain) break;
        {
            StageTimer t(stats.broadPhaseMs);
            RUBBLE_TRY(s.collision->broadPhase(collisionScene, bodies, p, contacts));
        }
        {
            StageTimer t(stats.narrowPhaseMs);
            RUBBLE_TRY(s.collision->narrowPhase(collisionScene, bodies, p, contacts));
        }
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.buildContactRowsMs);
        s.solver->buildRows(solverScene, bodies, s.velocitiesAtStart, contacts, p);
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.solveMs);
        std::copy(bodies.velocities.begin(), bodies.velocities.end(),
                  s.velocitiesBeforeSolve.begin());
        RUBBLE_TRY(s.solver->solve(solverScene, bodies, s.velocitiesBeforeSolve, contacts, p));
        // The momenta are the state: they take up what the impulses did to the velocities.
        absorbVelocityChange(bodies.momenta, s.velocitiesBeforeSolve, bodies.velocities,
                             bodies.masses, bodies.poses);
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.integratePositionsMs);
        // A solver with substeps has moved the bodies in its solve.
        if (!s.solver->integratesPositions())
            integratePositions(bodies.poses, bodies.velocities, s.velocitiesAtStart, bodies.momenta,
                               bodies.masses, p.dt, p.symplectic());
        // Kinematic bodies given a target end the step on it (their velocities led there).
        for (const auto& [body, pose] : s.kinematicTargets) bodies.poses[body] = pose;
        s.kinematicTargets.clear();
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.solvePositionsMs);
        s.solver->solvePositions(solverScene, bodies, p);
    }
    RUBBLE_TRY(checkStop(s));
    {
        StageTimer t(stats.islandsMs);
        if (p.sleep) stats.asleep = s.solver->sleep(solverScene, bodies, contacts, p);
    }
    stats.pairCount = std::uint32_t(contacts.pairs.size());
    stats.contactCount = contacts.contactCount;
    stats.largestPenetration = contacts.largestPenetration;
    const std::span<const float> sweeps = s.solver->residuals();
    stats.solverResidual = sweeps.empty() ? 0.0f : sweeps.back();
    return {};
}

} // namespace rubble
