// host/gpu/forces.h: the device's inputs of a step's forces (kernels/forces.cl): explosions on
// its bodies, and the host's bodies placed as obstacles with the impulses the rows put on them
// (debris offloading). The CPU path of explosions is host/dynamics/forces.cpp.
#pragma once

#include <span>
#include <vector>

#include "host/gpu/device_bodies.h"
#include "rubble/scene.h"
#include "rubble/shared/contact_row.h"
#include "rubble/shared/obstacle.h"

namespace rubble::gpu {

/// An explosion's impulse on the bodies within its radius; wakes them (enqueued).
Status applyExplosion(StageQueue& q, DeviceBodies& b, const EventDesc& e);

/// What the host gives the scene's kinematic bodies between steps, without a round trip of the
/// bodies: their velocities at the start of a step (World::setVelocity, setKinematicTarget) and
/// the poses they reach at its end (setKinematicTarget), written over where their velocities
/// took them, as the CPU's step does.
class KinematicTargets {
  public:
    /// Enqueues the velocities and flags of `states` (body, velocity and flags; the pose is not
    /// read), copied, so that `states` may go, and counts the bodies that move. Errors: Device.
    Status setVelocities(StageQueue& q, DeviceBodies& b,
                         std::span<const shared::ObstacleState> states);
    /// Enqueues the poses of `targets` (body, pose, velocity and flags), copied, so that
    /// `targets` may go. Errors: Device.
    Status place(StageQueue& q, DeviceBodies& b, std::span<const shared::ObstacleState> targets);

  private:
    Buffer velocities_, states_;
    std::vector<shared::ObstacleState> velocitiesHost_, statesHost_;
};

/// The host's bodies on the device: kinematic there, placed every step, and the impulses the
/// device's contact rows put on them (two-way coupling).
class ObstacleCoupling {
  public:
    /// The obstacles are the bodies `b.kinematic` marks, in index order. Errors: Device.
    Status create(StageQueue& q, const DeviceBodies& b);
    std::uint32_t count() const { return count_; }
    /// This step's obstacle states, one per obstacle (enqueued; copied, so `states` may go).
    Status place(StageQueue& q, DeviceBodies& b, std::span<const shared::ObstacleState> states);
    /// The summed impulse of the contact rows (per-body lists of the Jacobi solve) on each
    /// obstacle, read without waiting: impulses() holds them once the step is met.
    Status gather(StageQueue& q, const Buffer& rows, const Buffer& bodyStart,
                  const Buffer& bodyList);
    std::span<const shared::BodyImpulse> impulses() const { return impulsesHost_; }

  private:
    std::uint32_t count_ = 0;
    Buffer states_, bodies_, impulses_;
    std::vector<shared::ObstacleState> statesHost_;
    std::vector<shared::BodyImpulse> impulsesHost_;
};

} // namespace rubble::gpu
