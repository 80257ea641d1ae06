// host/gpu/sleep.h: sleeping on the device. Each body by itself on the device (kernels/sleep.cl:
// particles, or --body-sleep): the sleeping bodies a waking one touches wake before the rows,
// and after the step restless marks from the contacts decide each body's sleep. Or, with SAT, by
// islands (DeviceIslands, kernels/islands.cl), so that the device sleeps and wakes as the CPU
// does. The CPU twins are in host/dynamics/sleep.cpp and islands.cpp.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

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

/// Islands and their sleep on the device (SAT): the CPU's wakeIslands and updateSleep
/// (host/dynamics/islands.cpp) as kernels over this step's pairs with rows (the summaries'
/// RUBBLE_PGS_POINTS) and the joints, with the CPU's state between steps (each body's slow time,
/// the group it fell asleep with, whether it was asleep at the last step's end), so that the
/// device sleeps and wakes as the CPU does. The host reads nothing of its own: the counts come
/// with the status blocks the step reads anyway.
class DeviceIslands {
  public:
    /// The per-body state and scratch; `radii` each body's bounding radius, m. Errors: Device.
    Status create(StageQueue& q, const DeviceBodies& b, std::span<const float> radii);
    /// The bodies asleep by the host's flags (at load and after each upload).
    void reset(const DeviceBodies& b);
    /// Stage wake, after a collision round's summaries and before its status read, when a body
    /// is asleep: the sleeping bodies that the round's pairs with rows (with
    /// `kinematicTouches`, also the pairs with points between a moving kinematic body and a
    /// sleeping one) and the joints join to a restless body wake, with their groups; counted in
    /// RUBBLE_STATUS_WOKEN. A round whose pairs overflowed wakes none. Errors: Device.
    Status wake(StageQueue& q, DeviceBodies& b, const PairStore& pairs, const DeviceJoints& joints,
                bool kinematicTouches);
    /// Stage sleep, once the step has run: the islands on the step's velocities; an island slow
    /// for long enough sleeps (velocities and momenta zeroed), the sleeping bodies of a restless
    /// one wake. Counts go to RUBBLE_STATUS_ASLEEP, _WOKEN and _FELL_ASLEEP. Errors: Device.
    Status update(StageQueue& q, DeviceBodies& b, const PairStore& pairs,
                  const DeviceJoints& joints, float dt);
    /// The step's status block once met, after an update: the bodies asleep after it. Returns
    /// whether the update put any body to sleep or woke any.
    bool met(const DeviceStatus& st);
    /// Adds the buffers a step reads from the step before and writes (slow times, groups, last
    /// step's sleep) to `state`.
    void addStepState(std::vector<const Buffer*>& state) const {
        state.insert(state.end(), {&slowFor_, &group_, &wasAsleep_});
    }
    /// Bodies asleep at the end of the last step (or as uploaded).
    std::uint32_t asleep() const { return asleep_; }

  private:
    Status prepare(StageQueue& q, const DeviceBodies& b);
    bool prepared_ = false; ///< the state was taken from the flags (prepareIslands)
    std::uint32_t asleep_ = 0;
    std::uint32_t roundsWoken_ = 0; ///< bodies the step's collision rounds woke (status)
    Buffer radii_;                  ///< per body: bounding radius, m
    Buffer slowFor_;                ///< per body: how long it has been slow, s
    Buffer group_;         ///< per body: the island it fell asleep with (RUBBLE_NO_ISLAND: none)
    Buffer wasAsleep_;     ///< per body: asleep at the end of the last step
    Buffer restless_;      ///< per body: restless, this pass's
    Buffer marks_;         ///< per body: RUBBLE_ISLAND_WAKE_* of a collision round
    Buffer labels_;        ///< per body: its link toward its island's root
    Buffer groupFirst_;    ///< per group (a body index): its smallest member
    Buffer roots_;         ///< per body: its island's root
    Buffer island_;        ///< per root: RUBBLE_ISLAND_AWAKE and _RESTLESS
    Buffer islandSlowFor_; ///< per root: the shortest slow time of its awake bodies, float bits
};

} // namespace rubble::gpu
