// host/world/frozen_contacts.cpp: the stages of cpu_step.cpp up to the contacts, once, and what
// the solve would see kept.
#include "host/world/frozen_contacts.h"

#include <algorithm>
#include <string>

#include "host/collision/collision_world.h"
#include "host/collision/particle_world.h"
#include "host/core/integrate.h"
#include "host/core/math.h"
#include "host/dynamics/forces.h"
#include "host/dynamics/jacobi.h"
#include "host/world/world_state.h"

namespace rubble {

Result<FrozenContacts> freezeContacts(World& world, std::int64_t step) {
    if (step < 1)
        return makeError(ErrorKind::BadInput, "--step",
                         "must be 1 or more, got " + std::to_string(step));
    WorldState& s = world.state();
    if (s.device)
        return makeError(ErrorKind::BadInput, "solvers",
                         "contact sets are taken from the cpu backend's reference pipeline");
    for (std::int64_t i = 1; i < step; ++i) RUBBLE_TRY(world.step());

    // Stages 1 to 4 of cpu_step.cpp, with every body awake.
    for (BodyMass& m : s.masses) m.flags &= ~RUBBLE_BODY_ASLEEP;
    for (std::size_t e = 0; e < s.events.size(); ++e) {
        if (s.eventFired[e] || s.time() + 1e-9 < double(s.events[e].time)) continue;
        applyExplosion(s.events[e], s.poses, s.masses, s.momenta);
        s.eventFired[e] = 1;
    }
    integrateVelocities(s.momenta, s.forces, s.masses, s.poses, s.velocities, s.velocitiesAtStart,
                        toFloat4(s.options.gravity), s.options.dt);
    FrozenContacts set;
    if (s.options.collisionMethod() == CollisionMethod::Particles) {
        runParticleGrid(s);
        runParticleCollide(s);
        set.contacts = s.particles.contacts;
    } else {
        runBroadPhase(s);
        runNarrowPhase(s);
        manifoldsToContacts(s.manifolds, set.contacts);
    }
    set.step = step;
    set.poses = s.poses;
    set.velocities = s.velocities;
    set.masses = s.masses;
    set.surfaces = bodySurfaces(s);
    set.solver = s.options.solver;
    set.params = solverParams(s.options);
    return set;
}

} // namespace rubble
