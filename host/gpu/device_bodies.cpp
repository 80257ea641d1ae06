// host/gpu/device_bodies.cpp: the device's body arrays, their uploads and read-backs.
#include "host/gpu/device_bodies.h"

#include <algorithm>

#include "host/core/assert.h"
#include "rubble/shared/contact_row.h"

namespace rubble::gpu {

Status DeviceBodies::create(StageQueue& q, BodiesView bodies,
                            std::span<const shared::float4> bodySurfaces,
                            std::span<const std::uint8_t> hostStepped) {
    const Context& c = q.c();
    const std::size_t n = bodies.count();
    count = std::uint32_t(n);
    kinematic.assign(n, 0);
    std::copy(hostStepped.begin(), hostStepped.begin() + std::min(hostStepped.size(), n),
              kinematic.begin());
    RUBBLE_TRY(atStart.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(before.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(jacobi.reserve(c.context(), n * sizeof(shared::JacobiBody)));
    RUBBLE_TRY(slowFor.reserve(c.context(), n * sizeof(cl_float)));
    RUBBLE_TRY(restless.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(fill(c, slowFor, 0u, n * sizeof(cl_float)));
    RUBBLE_TRY(fill(c, restless, 0u, n * sizeof(cl_uint)));
    RUBBLE_TRY(gpu::upload(c, forces, bodies.forces));
    RUBBLE_TRY(gpu::upload(c, surfaces, bodySurfaces));
    return upload(q, bodies);
}

Status DeviceBodies::upload(StageQueue& q, BodiesView bodies) {
    const Context& c = q.c();
    RUBBLE_TRY(gpu::upload(c, poses, bodies.poses));
    RUBBLE_TRY(gpu::upload(c, velocities, bodies.velocities));
    RUBBLE_TRY(gpu::upload(c, atStart, bodies.velocities));
    RUBBLE_TRY(gpu::upload(c, momenta, bodies.momenta));
    // Kinematic bodies are walls on the device; the host's bodies (debris offloading) have their
    // flags set by the host each step, the scene's kinematic bodies move by their velocities
    // (integratePositions) and wake what they touch while those are not zero.
    deviceMasses.assign(bodies.masses.begin(), bodies.masses.end());
    std::vector<cl_uint> deviceFlags(deviceMasses.size());
    moving = 0;
    movingKinematic = 0;
    kinematicMoves.assign(deviceMasses.size(), 0);
    for (std::size_t i = 0; i < deviceMasses.size(); ++i) {
        deviceFlags[i] = deviceMasses[i].flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP);
        if (kinematic[i]) {
            deviceMasses[i] = shared::wallMassItem(deviceMasses[i]);
            deviceFlags[i] = RUBBLE_BODY_KINEMATIC;
        } else if (deviceMasses[i].flags & RUBBLE_BODY_KINEMATIC) {
            const bool moves = shared::movesAtAllItem(bodies.velocities[i]);
            deviceFlags[i] = RUBBLE_BODY_KINEMATIC | (moves ? RUBBLE_BODY_WAKING : 0u);
            // Never asleep: the world is not at rest while it moves.
            moving += moves ? 1u : 0u;
            movingKinematic += moves ? 1u : 0u;
            kinematicMoves[i] = moves ? 1u : 0u;
        } else if (!(deviceMasses[i].flags & RUBBLE_BODY_STATIC)) {
            ++moving;
        }
    }
    RUBBLE_TRY(gpu::upload(c, masses, deviceMasses));
    return gpu::upload(c, flags, deviceFlags);
}

void DeviceBodies::setKinematicMotion(std::uint32_t body, bool moves) {
    RUBBLE_ASSERT(body < kinematicMoves.size());
    const bool moved = kinematicMoves[body] != 0;
    if (moves == moved) return;
    kinematicMoves[body] = moves ? 1u : 0u;
    if (moves) {
        ++moving;
        ++movingKinematic;
    } else {
        --moving;
        --movingKinematic;
    }
}

Status DeviceBodies::uploadForces(StageQueue& q, std::span<const shared::BodyForce> bodyForces) {
    RUBBLE_TRY(gpu::upload(q.c(), forces, bodyForces));
    forcesOnDevice = true;
    return {};
}

Status DeviceBodies::clearForces(StageQueue& q) {
    if (!forcesOnDevice) return {};
    forcesOnDevice = false;
    return fill(q.c(), forces, 0u, std::size_t(count) * sizeof(shared::BodyForce), &q.profile());
}

Status DeviceBodies::enqueueRead(StageQueue& q, Bodies bodies, bool timed) {
    const Context& c = q.c();
    Profile* profile = timed ? &q.profile() : nullptr;
    flagsHost.resize(count);
    RUBBLE_TRY(enqueueDownload(c, poses, bodies.poses, profile));
    RUBBLE_TRY(enqueueDownload(c, velocities, bodies.velocities, profile));
    RUBBLE_TRY(enqueueDownload(c, momenta, bodies.momenta, profile));
    return enqueueDownload(c, flags, std::span(flagsHost), profile);
}

void DeviceBodies::takeSleepFlags(Bodies bodies) const {
    for (std::size_t i = 0; i < flagsHost.size(); ++i) {
        if (kinematic[i]) continue; // the host's own flags
        bodies.masses[i].flags =
            (bodies.masses[i].flags & ~RUBBLE_BODY_ASLEEP) | (flagsHost[i] & RUBBLE_BODY_ASLEEP);
    }
}

Status DeviceBodies::copyVelocities(StageQueue& q, const Buffer& to) {
    return q.copy(velocities, to, std::size_t(count) * sizeof(shared::BodyVelocity));
}

} // namespace rubble::gpu
