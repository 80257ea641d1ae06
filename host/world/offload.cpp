// host/world/offload.cpp: splitting a scene into its device and CPU populations, and what passes
// between them each step (obstacle states one way, impulses the other).
#include "host/world/offload.h"

#include <algorithm>

#include "host/core/math.h"
#include "host/world/world_state.h"
#include "rubble/shared/sleep.h"

namespace rubble {

bool hasDebrisSet(const Scene& scene) {
    return std::any_of(scene.bodies.begin(), scene.bodies.end(),
                       [](const BodyDesc& b) { return b.debris && !b.isStatic; });
}

SolverType deviceSolver(const Scene& scene) {
    const SolverType t = scene.simulation.solverType();
    return t == SolverType::Pgs && hasDebrisSet(scene) ? SolverType::Jacobi : t;
}

std::vector<std::uint8_t> deviceBodies(const Scene& scene) {
    const std::size_t n = scene.bodies.size();
    std::vector<std::uint8_t> onDevice(n, 0);
    const bool debrisSet = hasDebrisSet(scene);
    std::vector<std::uint8_t> jointed(n, 0);
    for (const JointDesc& j : scene.joints) jointed[j.a] = jointed[j.b] = 1;
    for (std::size_t i = 0; i < n; ++i) {
        const BodyDesc& b = scene.bodies[i];
        if (b.isStatic) continue;
        onDevice[i] = debrisSet ? (b.debris ? 1 : 0) : (jointed[i] ? 0 : 1);
    }
    return onDevice;
}

Result<std::unique_ptr<Offload>>
makeOffload(const Scene& scene, const std::vector<std::uint8_t>& onDevice, const RunOptions& run) {
    auto o = std::make_unique<Offload>();
    o->coupling = scene.simulation.coupling;
    const std::size_t n = scene.bodies.size();
    o->worldToCpu.assign(n, kNotOnCpu);
    o->kinematic.assign(n, 0);
    // The CPU world's scene: its bodies in world order, joints renumbered, the reference
    // pipeline's collision and solver with the scene's settings.
    Scene cpuScene = scene;
    cpuScene.bodies.clear();
    cpuScene.joints.clear();
    cpuScene.simulation.backend = Backend::Cpu;
    cpuScene.simulation.collision.method = CollisionMethod::Sat;
    cpuScene.simulation.solver.type = SolverType::Pgs;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (onDevice[i]) continue;
        const BodyDesc& b = scene.bodies[i];
        o->worldToCpu[i] = std::uint32_t(o->cpuToWorld.size());
        o->cpuToWorld.push_back(i);
        cpuScene.bodies.push_back(b);
        if (b.isStatic) continue;
        o->kinematic[i] = 1;
        o->obstacles.push_back(o->worldToCpu[i]);
    }
    for (JointDesc j : scene.joints) {
        j.a = o->worldToCpu[j.a];
        j.b = o->worldToCpu[j.b];
        cpuScene.joints.push_back(j);
    }
    Result<World> cpu = World::create(cpuScene, run);
    RUBBLE_TRY(cpu);
    o->cpu = std::make_unique<World>(std::move(*cpu));
    o->states.resize(o->obstacles.size());
    o->pending.assign(o->obstacles.size(), shared::BodyImpulse{});
    return o;
}

void prepareObstacles(Offload& o) {
    WorldState& c = WorldAccess::state(*o.cpu);
    for (std::size_t k = 0; k < o.obstacles.size(); ++k) {
        const std::uint32_t i = o.obstacles[k];
        shared::BodyImpulse& j = o.pending[k];
        // Two-way: the debris' push of the last step, as an impulse about the centre of mass.
        if (j.linear.x != 0.0f || j.linear.y != 0.0f || j.linear.z != 0.0f || j.angular.x != 0.0f ||
            j.angular.y != 0.0f || j.angular.z != 0.0f) {
            c.bodies.momenta[i].linear = shared::add4(c.bodies.momenta[i].linear, j.linear);
            c.bodies.momenta[i].angular = shared::add4(c.bodies.momenta[i].angular, j.angular);
            c.bodies.velocities[i] =
                shared::velocityFromMomentumItem(c.bodies.momenta[i], c.bodies.masses[i], c.bodies.poses[i].orientation);
            c.bodies.masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
        }
        j = shared::BodyImpulse{};
        shared::ObstacleState& st = o.states[k];
        st.pose = c.bodies.poses[i];
        st.velocity = c.bodies.velocities[i];
        st.body = o.cpuToWorld[i];
        // A moving obstacle wakes the sleeping debris it touches.
        st.flags =
            RUBBLE_BODY_KINEMATIC | (shared::slowBodyItem(st.velocity) ? 0u : RUBBLE_BODY_WAKING);
    }
}

void copyCpuBodies(const Offload& o, WorldState& s) {
    const WorldState& c = WorldAccess::state(*o.cpu);
    for (std::uint32_t i = 0; i < c.bodyCount(); ++i) {
        const std::uint32_t w = o.cpuToWorld[i];
        s.bodies.poses[w] = c.bodies.poses[i];
        s.bodies.velocities[w] = c.bodies.velocities[i];
        s.bodies.momenta[w] = c.bodies.momenta[i];
        s.bodies.masses[w].flags = c.bodies.masses[i].flags;
    }
}

} // namespace rubble
