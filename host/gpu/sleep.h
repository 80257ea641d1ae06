// host/gpu/sleep.h: sleeping on the device. Each body by itself on the device (kernels/sleep.cl:
// particles, or --body-sleep): the sleeping bodies a waking one touches wake before the rows,
// and after the step restless marks from the contacts decide each body's sleep. Or, with SAT,
// as the host decides with the world's islands (HostIslands over a HostSleep), so that the
// device sleeps and wakes as the CPU does. The CPU twins are in host/dynamics/sleep.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "host/collision/contact.h"
#include "host/gpu/joints.h"
#include "host/gpu/pairs.h"
#include "host/gpu/particles.h"
#include "rubble/shared/broad_phase.h"

namespace rubble::gpu {

/// Particles: the sleeping bodies that this step's contacts touch with a waking body wake.
Status wakeTouched(StageQueue& q, DeviceBodies& b, const ContactBuffers& k);
/// Pairs: the sleeping bodies that a pair with points joins to a waking body wake, and with
/// them the joint groups of woken members. In round `round` > 0 of a step's collision the bodies
/// woken in earlier rounds wake those they touch as well; round 0 takes no marks.
Status wakeTouchedPairs(StageQueue& q, DeviceBodies& b, const PairStore& pairs,
                        const DeviceJoints& joints, std::uint32_t round);
/// SAT, in collision round `round`: the sleeping bodies that last step's entries with impulses
/// join to a body woken in an earlier round wake.
Status wakeStillPairs(StageQueue& q, DeviceBodies& b, const PairStore& pairs, std::uint32_t round);
/// Stage sleepBodies: restless marks from the rows (the pairs' manifolds and the joints when
/// `pairs` is given, else the Jacobi rows of `k`), joint groups held together, then each
/// body's sleep.
Status sleepBodies(StageQueue& q, DeviceBodies& b, const PairStore* pairs, const ContactBuffers* k,
                   const DeviceJoints& joints, float dt);

/// What a host-side sleep decision did (HostSleep::update).
struct HostSleepCounts {
    std::uint32_t asleep = 0;     ///< bodies asleep after it
    std::uint32_t fellAsleep = 0; ///< bodies it put to sleep (their velocities and momenta zeroed)
    std::uint32_t woken = 0;      ///< bodies it woke
};

/// Sleep decided on the host. host/world implements it with the CPU's islands, so that the
/// device sleeps and wakes as the CPU does; host/gpu does not include host/dynamics.
class HostSleep {
  public:
    virtual ~HostSleep() = default;
    /// After a collision round, when a body is asleep: wakes what this round's contacts
    /// (`touching`) and the joints join to a restless body, on `approach` (the velocities before
    /// the forces), by clearing RUBBLE_BODY_ASLEEP in `masses`. Returns the bodies it woke.
    virtual std::uint32_t wake(std::span<const BodyPair> touching,
                               std::span<shared::BodyMass> masses,
                               std::span<const shared::BodyVelocity> approach) = 0;
    /// Once the step has run: each body's sleep on the step's velocities; a body put to sleep
    /// has RUBBLE_BODY_ASLEEP set in `masses` and its velocities and momenta zeroed.
    virtual HostSleepCounts update(std::span<const BodyPair> touching,
                                   std::span<shared::BodyMass> masses,
                                   std::span<shared::BodyVelocity> velocities,
                                   std::span<shared::BodyMomentum> momenta, float dt) = 0;
};

/// The device's side of a HostSleep: the host's copy of the masses and flags, and the arrays
/// it reads from the device.
class HostIslands {
  public:
    explicit HostIslands(std::shared_ptr<HostSleep> sleep) : sleep_(std::move(sleep)) {}
    /// The host's flags are the islands' from here on (at load and after each upload).
    void reset(const DeviceBodies& b);
    /// A new step: the flags and approach velocities are read again in its first wake.
    void beginStep() { stepRead_ = false; }
    /// After a collision round (the status read after the summaries, `touching` its pairs with
    /// rows), when a body is asleep: HostSleep::wake; the woken bodies' flags go to the device.
    /// Returns the bodies it woke (the caller collides again). Errors: Device.
    Result<std::uint32_t> wake(StageQueue& q, DeviceBodies& b, std::span<const BodyPair> touching);
    /// Once the step has run: HostSleep::update over its pairs with rows, on the velocities
    /// after the step (`readBack`'s, with b.flagsHost, else read here); the bodies that fell
    /// asleep are stopped on the device and in `readBack`, the flags go to the device (when it
    /// put any to sleep or woke any). Errors: Device.
    Result<HostSleepCounts> update(StageQueue& q, DeviceBodies& b,
                                   std::span<const BodyPair> touching, float dt,
                                   const std::optional<Bodies>& readBack);
    /// After a collision round, with a moving kinematic body: appends to `touching` this
    /// round's pairs with points that join one to a sleeping body (they have no rows, so the
    /// summaries leave them out); waits for them. Errors: Device.
    Status addKinematicTouches(StageQueue& q, const DeviceBodies& b, const PairStore& pairs,
                               std::vector<BodyPair>& touching);
    /// Bodies asleep after the last update (or reset).
    std::uint32_t asleep() const { return asleep_; }

  private:
    std::shared_ptr<HostSleep> sleep_;
    std::vector<shared::BodyMass> masses_; ///< the device's masses, the islands' flags
    std::uint32_t asleep_ = 0;
    bool stepRead_ = false; ///< flags and approach read in this step
    std::vector<cl_uint> flags_;
    std::vector<shared::BodyVelocity> approach_, velocities_;
    std::vector<shared::BodyMomentum> momenta_;
    Buffer touchCount_, touches_; ///< listKinematicTouches' count and pairs
    std::vector<shared::BodyPairRecord> touchesHost_;
};

} // namespace rubble::gpu
