// host/world/cpu_step.cpp: the CPU reference step as a list of stages, each timed.
#include "host/world/cpu_step.h"

#include <algorithm>
#include <chrono>

#include "host/collision/collision_world.h"
#include "host/core/integrate.h"
#include "host/core/math.h"
#include "host/dynamics/dynamics_world.h"
#include "host/dynamics/forces.h"
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

} // namespace

void stepCpuReference(WorldState& s, StepStats& stats) {
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
    {
        StageTimer t(stats.integrateVelocitiesMs);
        // Explicit Euler moves positions with the velocities the step started with.
        if (!symplectic) std::copy(s.velocities.begin(), s.velocities.end(), s.velocitiesAtStart.begin());
        integrateVelocities(s.momenta, s.forces, s.masses, s.poses, s.velocities,
                            toFloat4(s.options.gravity), dt);
    }
    {
        StageTimer t(stats.broadPhaseMs);
        runBroadPhase(s);
    }
    {
        StageTimer t(stats.narrowPhaseMs);
        runNarrowPhase(s);
    }
    {
        StageTimer t(stats.buildContactRowsMs);
        runBuildContactRows(s);
    }
    {
        StageTimer t(stats.solveMs);
        std::copy(s.velocities.begin(), s.velocities.end(), s.velocitiesBeforeSolve.begin());
        runSolveVelocities(s);
        // The momenta are the state: they take up what the impulses did to the velocities.
        absorbVelocityChange(s.momenta, s.velocitiesBeforeSolve, s.velocities, s.masses, s.poses);
    }
    {
        StageTimer t(stats.integratePositionsMs);
        integratePositions(s.poses, s.velocities, s.velocitiesAtStart, s.momenta, s.masses, dt,
                           symplectic);
    }
    {
        StageTimer t(stats.solvePositionsMs);
        runSolvePositions(s);
    }
    {
        StageTimer t(stats.islandsMs);
        runUpdateSleep(s);
    }
}

} // namespace rubble
