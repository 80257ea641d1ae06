// host/world/cpu_step.cpp: the CPU reference step as a list of stages, each timed.
#include "host/world/cpu_step.h"

#include <algorithm>
#include <chrono>

#include "host/collision/collision_world.h"
#include "host/collision/particle_world.h"
#include "host/core/integrate.h"
#include "host/core/math.h"
#include "host/dynamics/body_sleep.h"
#include "host/dynamics/dynamics_world.h"
#include "host/dynamics/forces.h"
#include "host/dynamics/jacobi_solvers.h"
#include "host/dynamics/lcp_jacobi.h"
#include "host/world/step_stop.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// Adds the wall time of its scope to a StepStats field, in milliseconds.
class StageTimer {
  public:
    explicit StageTimer(double& total) : total_(total), start_(Clock::now()) {}
    ~StageTimer() {
        total_ += std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
    }
    StageTimer(const StageTimer&) = delete;
    StageTimer& operator=(const StageTimer&) = delete;

  private:
    using Clock = std::chrono::steady_clock;
    double& total_;
    Clock::time_point start_;
};

std::optional<Error> statusError(const Status& s) {
    if (s.ok()) return std::nullopt;
    return s.error();
}

} // namespace

void stepCpuReference(WorldState& s, StepStats& stats) {
    s.stepFailure.reset();
    const float dt = s.options.dt;
    const bool symplectic = s.options.integrator == Integrator::Symplectic;
    {
        StageTimer t(stats.applyForcesMs);
        for (std::size_t e = 0; e < s.events.size(); ++e) {
            if (s.eventFired[e] || s.time() + 1e-9 < double(s.events[e].time)) continue;
            applyExplosion(s.events[e], s.poses, s.masses, s.momenta);
            s.eventFired[e] = 1;
        }
    }
    if (stepMustStop(s)) return;
    {
        StageTimer t(stats.integrateVelocitiesMs);
        // Explicit Euler moves positions with the velocities the step started with.
        if (!symplectic) std::copy(s.velocities.begin(), s.velocities.end(), s.velocitiesAtStart.begin());
        integrateVelocities(s.momenta, s.forces, s.masses, s.poses, s.velocities,
                            toFloat4(s.options.gravity), dt);
    }
    if (stepMustStop(s)) return;
    // The particle method and the solvers other than PGS are the OpenCL stages' CPU twins.
    const bool particles = s.options.collisionMethod() == CollisionMethod::Particles;
    const bool pgs = s.options.solver.type == SolverType::Pgs;
    const bool lcp = s.options.solver.type == SolverType::LcpJacobi;
    const bool lemke = s.options.solver.type == SolverType::Lemke;
    {
        StageTimer t(stats.broadPhaseMs);
        if (particles) runParticleGrid(s);
        else runBroadPhase(s);
    }
    if (stepMustStop(s)) return;
    {
        StageTimer t(stats.narrowPhaseMs);
        if (particles) runParticleCollide(s);
        else runNarrowPhase(s);
        if (particles && pgs) particleContactsToManifolds(s.particles.contacts, s.manifolds);
    }
    if (stepMustStop(s)) return;
    {
        StageTimer t(stats.buildContactRowsMs);
        if (pgs) runBuildContactRows(s);
        else runBuildSolverRows(s);
    }
    if (stepMustStop(s)) return;
    {
        StageTimer t(stats.solveMs);
        std::copy(s.velocities.begin(), s.velocities.end(), s.velocitiesBeforeSolve.begin());
        if (pgs) runSolveVelocities(s);
        else if (lcp) s.stepFailure = statusError(runSolveLcpJacobi(s));
        else if (lemke) s.stepFailure = statusError(runSolveLemke(s));
        else runSolveRows(s);
        // The momenta are the state: they take up what the impulses did to the velocities.
        absorbVelocityChange(s.momenta, s.velocitiesBeforeSolve, s.velocities, s.masses, s.poses);
    }
    if (stepMustStop(s)) return;
    {
        StageTimer t(stats.integratePositionsMs);
        integratePositions(s.poses, s.velocities, s.velocitiesAtStart, s.momenta, s.masses, dt,
                           symplectic);
    }
    if (stepMustStop(s)) return;
    {
        StageTimer t(stats.solvePositionsMs);
        runSolvePositions(s);
    }
    if (stepMustStop(s)) return;
    {
        StageTimer t(stats.islandsMs);
        // PGS sleeps by islands; the device's solvers sleep as the device does (its twin).
        if (pgs) runUpdateSleep(s);
        else if (!lemke) runSleepBodies(s);
    }
}

} // namespace rubble
