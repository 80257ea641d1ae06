// host/gpu/device_bodies.h: the bodies of a device world, one element per body in world order,
// uploaded at load and kept on the device; the host reads them back when asked.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/core/bodies.h"
#include "host/gpu/stage_queue.h"
#include "rubble/shared/body.h"

namespace rubble::gpu {

/// The body arrays every stage reads or writes, and what the host knows of them.
struct DeviceBodies {
    std::uint32_t count = 0;
    Buffer poses, velocities, momenta, forces, masses;
    Buffer flags;    ///< RUBBLE_BODY_* per body: the device's own (sleep, kinematic)
    Buffer slowFor;  ///< per body: how long it has been slow, s (sleeping)
    Buffer restless; ///< per body: RUBBLE_RESTLESS_* bits of this step's contacts
    Buffer atStart;  ///< velocities before the step's forces (restitution, explicit Euler)
    Buffer before;   ///< velocities before the solve
    Buffer jacobi;   ///< JacobiBody per body, this step's (prepareJacobiBodies)
    Buffer surfaces; ///< per body: friction, restitution
    /// Per body: the host steps it (debris offloading); it is an infinite mass on the device.
    std::vector<std::uint8_t> kinematic;
    /// The bodies that move (neither static nor kinematic), counted at each upload.
    std::uint32_t moving = 0;
    /// The scene's kinematic bodies whose velocity is not zero, counted at each upload and kept
    /// by setKinematicMotion.
    std::uint32_t movingKinematic = 0;
    /// Per body: a kinematic body of the scene whose velocity is not zero.
    std::vector<std::uint8_t> kinematicMoves;
    /// Masses as the device holds them (kinematic bodies as walls), as last uploaded.
    std::vector<shared::BodyMass> deviceMasses;
    bool forcesOnDevice = false;    ///< the force buffer holds non-zero forces
    std::vector<cl_uint> flagsHost; ///< the flags read by the last enqueueRead

    /// Sizes the arrays for `bodies` and uploads them. Errors: Device.
    Status create(StageQueue& q, BodiesView bodies, std::span<const shared::float4> surfaces,
                  std::span<const std::uint8_t> hostStepped);
    /// Copies the host's poses, velocities, momenta, masses and flags to the device (the
    /// velocities also as those before the forces, for stages run alone). Errors: Device.
    Status upload(StageQueue& q, BodiesView bodies);
    /// A kinematic body of the scene given a velocity by the host (not uploaded): whether it
    /// moves, in the counts above.
    void setKinematicMotion(std::uint32_t body, bool moves);
    /// This step's forces and torques. Errors: Device.
    Status uploadForces(StageQueue& q, std::span<const shared::BodyForce> forces);
    /// Forces hold for one step: cleared once a step used them (enqueued).
    Status clearForces(StageQueue& q);
    /// Enqueues the reads of poses, velocities, momenta and flags into `bodies` without waiting;
    /// takeSleepFlags merges the flags once the queue ran them. `timed`: in the step's profile.
    Status enqueueRead(StageQueue& q, Bodies bodies, bool timed);
    void takeSleepFlags(Bodies bodies) const;
    /// Copies the velocities into `to` (atStart, before, or a solver's scratch), enqueued.
    Status copyVelocities(StageQueue& q, const Buffer& to);
};

} // namespace rubble::gpu
