// host/world/frozen_contacts.cpp: the stages of cpu_step.cpp up to the contacts, once, and what
// the solve would see kept; the device solvers one sweep at a time on such a set.
#include "host/world/frozen_contacts.h"

#include <algorithm>
#include <string>

#include "host/core/integrate.h"
#include "host/core/step_params.h"
#include "host/dynamics/forces.h"
#include "host/gpu/lcp_jacobi.h"
#include "host/gpu/jacobi.h"
#include "host/world/world_state.h"

namespace rubble {

Result<FrozenContacts> freezeContacts(World& world, std::int64_t step) {
    if (step < 1)
        return makeError(ErrorKind::BadInput, "--step",
                         "must be 1 or more, got " + std::to_string(step));
    WorldState& s = WorldAccess::state(world);
    if (s.device)
        return makeError(ErrorKind::BadInput, "solvers",
                         "contact sets are taken from the cpu backend's reference pipeline");
    for (std::int64_t i = 1; i < step; ++i) RUBBLE_TRY(world.step());

    // Stages 1 to 4 of cpu_step.cpp, with every body awake.
    const StepParams p = makeStepParams(s.options, s.step);
    const Bodies bodies = s.bodies.view();
    for (BodyMass& m : bodies.masses) m.flags &= ~RUBBLE_BODY_ASLEEP;
    applyDueExplosions(s.events, s.eventFired, p.time, bodies);
    integrateVelocities(bodies.momenta, bodies.forces, bodies.masses, bodies.poses,
                        bodies.velocities, s.velocitiesAtStart, p.gravity, p.dt);
    RUBBLE_TRY(s.collision->broadPhase(s.collisionScene(), bodies, p, s.contacts));
    RUBBLE_TRY(s.collision->narrowPhase(s.collisionScene(), bodies, p, s.contacts));
    FrozenContacts set;
    s.collision->contactPoints(s.contacts, set.contacts);
    set.step = step;
    set.poses.assign(bodies.poses.begin(), bodies.poses.end());
    set.velocities.assign(bodies.velocities.begin(), bodies.velocities.end());
    set.masses.assign(bodies.masses.begin(), bodies.masses.end());
    set.surfaces = s.surfaces;
    set.solver = s.options.solver;
    set.params = p.rows;
    return set;
}

Result<Iterates> lcpJacobiIteratesOnDevice(const gpu::Context& c, const DenseLcp& p,
                                           int iterations, float relaxation) {
    const std::vector<float> zero(p.lambda.size(), 0.0f);
    gpu::HostLcp start{p.contacts, p.stride, p.matrix, p.rhs, p.inverseScale, p.friction, zero};
    gpu::LcpBuffers lcp;
    RUBBLE_TRY(gpu::uploadLcp(c, start, lcp));
    Iterates out;
    std::vector<float> lambda;
    for (int k = 0; k < iterations; ++k) {
        RUBBLE_TRY(gpu::iterateLcpJacobi(c, lcp, 1, relaxation, lcp.status));
        RUBBLE_TRY(gpu::downloadLcpLambda(c, lcp, lambda));
        out.push_back(lambda);
    }
    return out;
}

Result<Iterates> jacobiIteratesOnDevice(std::shared_ptr<gpu::Context> c, const FrozenProblem& p,
                                        int iterations, float relaxation) {
    const FrozenContacts& set = p.set;
    // The set's bodies as the device's (the solve reads no momenta or forces).
    const std::vector<shared::BodyMomentum> momenta(set.poses.size());
    const std::vector<shared::BodyForce> forces(set.poses.size());
    const BodiesView bodies{set.poses, set.velocities, momenta, forces, set.masses, {}, {}};
    // The stages the Jacobi solve needs, alone: the bodies, the contact buffers, the solve.
    Result<std::unique_ptr<gpu::StageQueue>> made = gpu::StageQueue::create(std::move(c));
    RUBBLE_TRY(made);
    gpu::StageQueue& q = **made;
    gpu::DeviceBodies device;
    RUBBLE_TRY(device.create(q, bodies, set.surfaces, {}));
    gpu::ParticleCollision particles;
    RUBBLE_TRY(particles.create(q, nullptr, bodies, nullptr));
    RUBBLE_TRY(particles.uploadContacts(q, set.contacts));
    gpu::JacobiSolve jacobi;
    gpu::ContactBuffers& k = particles.contacts();
    RUBBLE_TRY(jacobi.buildRows(q, device, k, 0, set.params, false));
    Iterates out;
    std::vector<shared::ContactRow> rows(set.contacts.size());
    for (int it = 0; it < iterations; ++it) {
        // The start velocities again; the rows keep the impulses of the last sweep, which the
        // first gather applies.
        RUBBLE_TRY(device.upload(q, bodies));
        RUBBLE_TRY(jacobi.solve(q, device, k, 1, relaxation));
        RUBBLE_TRY(gpu::download(q.c(), k.rows, std::span(rows)));
        out.push_back(denseLambda(rows, p.dense.stride));
    }
    return out;
}

} // namespace rubble
