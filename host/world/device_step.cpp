// host/world/device_step.cpp: the OpenCL backend of a World over host/gpu's Pipeline, and the
// meeting of an offloaded world's two halves.
#include "host/world/device_step.h"

#include <algorithm>
#include <chrono>

#include "host/collision/particles.h"
#include "host/core/clock.h"
#include "host/core/math.h"
#include "host/core/step_params.h"
#include "host/dynamics/forces.h"
#include "host/dynamics/joints.h"
#include "host/gpu/pipeline.h"
#include "host/world/blowup_check.h"
#include "host/world/offload.h"
#include "host/world/step_stop.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// A world without CPU bodies reports the device's stage times as its stages.
void deviceStagesAsStages(StepStats& stats) {
    const DeviceStageMs& d = stats.deviceStages;
    stats.applyForcesMs = d.applyForces;
    stats.integrateVelocitiesMs = d.integrateVelocities;
    stats.broadPhaseMs = d.broadPhase;
    stats.narrowPhaseMs = d.narrowPhase;
    stats.buildContactRowsMs = d.buildContactRows;
    stats.solveMs = d.solve;
    stats.integratePositionsMs = d.integratePositions;
    // The device's sleep stage (with SAT, its islands).
    stats.islandsMs += d.sleep;
}

} // namespace

Status attachDevice(WorldState& s, std::shared_ptr<gpu::Context> context,
                    const SimulationOptions& options) {
    s.options = options;
    s.options.backend = Backend::OpenCl;
    gpu::PipelineInput in;
    in.bodies = s.bodies.view();
    in.surfaces = s.surfaces;
    // SAT collides the shapes' hulls on the device; only particles need the voxelised shapes.
    Result<ParticleSet> particles = ParticleSet{};
    if (s.options.collisionMethod() == CollisionMethod::Sat) {
        in.collision = CollisionMethod::Sat;
        in.shapes = s.shapes;
        in.joined = s.joined;
        if (s.deviceJoints.size() != s.joints.size()) {
            s.deviceJoints.clear();
            for (const Joint& j : makeJoints(s.joints, s.bodies.poses))
                s.deviceJoints.push_back(sharedJoint(j));
        }
        in.joints = s.deviceJoints;
        // Islands, as the CPU sleeps, unless each body is to sleep by itself.
        in.islands = !s.run.bodySleep;
    } else {
        in.particlePgs = s.options.solverType() == SolverType::Pgs;
        particles = buildParticleSet(s.shapes, s.materials, s.bodies.view(),
                                     s.options.collision.particleSpacing, in.particlePgs);
        RUBBLE_TRY(particles);
        in.particles = &*particles;
    }
    if (s.offload) in.kinematic = s.offload->kinematic;
    in.deterministic = s.run.deterministic;
    in.pgsBlocks = s.run.pgsBlocks;
    in.pgsColoring = resolvePgsColoring(s.run.pgsColoring, s.options.solverType());
    Result<gpu::PipelineHandle> p = gpu::Pipeline::create(std::move(context), in);
    RUBBLE_TRY(p);
    s.device = std::move(*p);
    s.deviceEnergy = {};
    s.deviceKinematic =
        std::any_of(s.bodies.masses.begin(), s.bodies.masses.end(),
                    [](const BodyMass& m) { return m.flags & RUBBLE_BODY_KINEMATIC; });
    s.hostStale = false;
    s.hostDirty = false;
    s.forcesDirty = false;
    return {};
}

Status attachScene(WorldState& s, const Scene& scene, std::shared_ptr<gpu::Context> context,
                   const RunOptions& run) {
    s.offload.reset();
    // With SAT every body steps on the device (PGS has joint rows there); with particles the
    // bodies the device does not step get a CPU world.
    const bool sat = scene.simulation.collisionMethod() == CollisionMethod::Sat;
    const std::vector<std::uint8_t> onDevice = deviceBodies(scene);
    for (std::size_t i = 0; i < scene.bodies.size() && !sat; ++i) {
        if (scene.bodies[i].isStatic || onDevice[i]) continue;
        Result<std::unique_ptr<Offload>> offload = makeOffload(scene, onDevice, run);
        RUBBLE_TRY(offload);
        s.offload = std::move(*offload);
        break;
    }
    SimulationOptions options = scene.simulation;
    options.backend = Backend::OpenCl;
    // The options in effect: SAT feeds PGS or the soft step, particles the scene's solver
    // (deviceSolver: the Jacobi family for a debris set).
    options.collision.method = options.collisionMethod();
    const SolverType satSolver = scene.simulation.solverType() == SolverType::SoftStep
                                     ? SolverType::SoftStep
                                     : SolverType::Pgs;
    options.solver.type = sat ? satSolver : deviceSolver(scene);
    return attachDevice(s, std::move(context), options);
}

Status syncHost(WorldState& s) {
    if (!s.device || !s.hostStale) return {};
    RUBBLE_TRY(s.device->downloadBodies(s.bodies.view()));
    if (s.offload) copyCpuBodies(*s.offload, s);
    s.hostStale = false;
    return {};
}

Status beginHostChange(WorldState& s) {
    RUBBLE_TRY(syncHost(s));
    if (s.device) s.hostDirty = true;
    return {};
}

void noteKinematicVelocity(WorldState& s, std::uint32_t i) {
    if (!s.device) return;
    std::vector<std::uint32_t>& set = s.kinematicVelocitySet;
    if (std::find(set.begin(), set.end(), i) == set.end()) set.push_back(i);
}

Status stepDevice(WorldState& s, StepStats& stats) {
    RUBBLE_TRY(checkStop(s));
    const auto start = std::chrono::steady_clock::now();
    gpu::Pipeline& p = *s.device;
    Offload* o = s.offload.get();
    const StepParams params = makeStepParams(s.options, s.step);
    if (s.hostDirty) {
        RUBBLE_TRY(p.uploadBodies(s.bodies.view()));
        s.hostDirty = false;
    }
    if (s.forcesDirty) {
        RUBBLE_TRY(p.uploadForces(s.bodies.forces));
        s.forcesDirty = false;
    }
    // Explosions due this step act on the device's bodies there (the CPU world has its own).
    s.dueEvents.clear();
    for (std::size_t e = 0; e < s.events.size(); ++e) {
        if (!eventDue(s.events[e], s.eventFired[e], params.time)) continue;
        s.dueEvents.push_back(s.events[e]);
        s.eventFired[e] = 1;
    }
    // A world at rest with nothing new for the device (the uploads above, if any, tell
    // Pipeline::atRest so): its step would change nothing there, and the last step's energy sum
    // (or the host's copy) stands for it in the blow-up watch.
    // World::step cleared `stats`: no contacts, no device time.
    if (!o && s.dueEvents.empty() && s.kinematicVelocitySet.empty() && s.kinematicTargets.empty() &&
        p.atRest()) {
        stats.asleep = stats.deviceAsleep = p.asleepBodies();
        stats.hostMs = msSince(start);
        return {};
    }
    gpu::StepInputs in;
    in.explosions = s.dueEvents;
    if (o) {
        prepareObstacles(*o);
        in.obstacles = o->states;
        in.gatherObstacleImpulses = o->coupling == Coupling::TwoWay;
    }
    // A kinematic body's record for the device: its velocity in the host's copy, and whether it
    // moves (then it wakes what it touches).
    auto kinematicState = [&s](std::uint32_t body) {
        shared::ObstacleState k{};
        k.velocity = s.bodies.velocities[body];
        k.body = body;
        k.flags = RUBBLE_BODY_KINEMATIC |
                  (shared::movesAtAllItem(k.velocity) ? RUBBLE_BODY_WAKING : 0u);
        return k;
    };
    // Kinematic bodies given a target this step (World::setKinematicTarget) end on it.
    s.deviceTargets.clear();
    for (const auto& [body, pose] : s.kinematicTargets) {
        s.deviceTargets.push_back(kinematicState(body));
        s.deviceTargets.back().pose = pose;
    }
    s.kinematicTargets.clear();
    in.kinematicTargets = s.deviceTargets;
    // Kinematic bodies given a velocity since the last step move by it from this step's start.
    s.deviceVelocities.clear();
    for (const std::uint32_t body : s.kinematicVelocitySet)
        s.deviceVelocities.push_back(kinematicState(body));
    s.kinematicVelocitySet.clear();
    in.kinematicVelocities = s.deviceVelocities;
    // Without a CPU world the step ends by summing the bodies' energy for the blow-up watch;
    // a step that starts the watch again reads the bodies back as well, in the step's queue, so
    // that the host waits once, not twice. Other steps leave the host's copy stale (syncHost).
    if (!o) {
        in.sumEnergy = true;
        in.restartEnergy = watchReadsBodies(s);
        if (in.restartEnergy) in.readBack = s.bodies.view();
    }
    // The device's step is enqueued first; the CPU world steps while it runs; they meet.
    RUBBLE_TRY(p.beginStep(params, in));
    s.hostStale = true;
    Status cpuStepped;
    if (o) cpuStepped = o->cpu->step();
    const Status met = p.endStep(params, s.names, stats);
    if (met.ok() && in.readBack) s.hostStale = false;
    if (o && in.gatherObstacleImpulses) {
        const std::span<const shared::BodyImpulse> j = p.obstacleImpulses();
        std::copy(j.begin(), j.end(), o->pending.begin());
    }
    if (o) {
        // The CPU world's stages are this step's stages; contacts add up.
        const StepStats& c = o->cpu->lastStep();
        const StepStats device = stats;
        stats = c;
        stats.deviceMs = device.deviceMs;
        stats.deviceWaitMs = device.deviceWaitMs;
        stats.deviceStages = device.deviceStages;
        stats.deviceContactCount = device.deviceContactCount;
        stats.deviceAsleep = device.deviceAsleep;
        stats.deviceWaits = device.deviceWaits;
        stats.asleep = c.asleep + device.deviceAsleep;
        stats.contactCount = c.contactCount + device.deviceContactCount;
        stats.largestPenetration = std::max(c.largestPenetration, device.largestPenetration);
        stats.solverResidual = std::max(c.solverResidual, device.solverResidual);
    } else {
        deviceStagesAsStages(stats);
        stats.contactCount = stats.deviceContactCount;
    }
    stats.hostMs = msSince(start) - stats.deviceWaitMs;
    stats.deviceHiddenMs = std::max(0.0, stats.deviceMs - stats.deviceWaitMs);
    RUBBLE_TRY(met);
    return cpuStepped;
}

} // namespace rubble
