// host/gpu/stage_queue.h: what every device stage enqueues on: the context's queue, the profile
// that times the step's commands, and the status block (RUBBLE_STATUS_* slots) in which stages
// count what they made and the host reads once a step is met, and a copy of it taken on the device
// after a step's collision round, read with it.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "host/gpu/buffer.h"
#include "host/gpu/context.h"
#include "host/gpu/profile.h"
#include "rubble/shared/constants.h"

namespace rubble::gpu {

/// The status block as the host reads it.
struct DeviceStatus {
    std::uint32_t contacts = 0;
    std::uint32_t firstNonFinite = 0xffffffffu; ///< a body index, or none
    float largestPenetration = 0;               ///< m
    float solverResidual = 0;                   ///< N s
    std::uint32_t capacity = 0;
    std::uint32_t asleep = 0, woken = 0;
    std::uint32_t fellAsleep = 0; ///< SAT islands: bodies put to sleep at the end of the step
    std::uint32_t pairs = 0;      ///< SAT: body pairs the broad phase found (may exceed the room)
    std::uint32_t gridEntries = 0, largeBodies = 0; ///< SAT: the broad phase's grid
    /// SAT: last step's kept pair entries as markStillPairs saw them, and the still pairs
    /// carried into this step's set; both 0 when the carry did not run.
    std::uint32_t kept = 0, carried = 0;
    /// PGS: impulse slots taken in the pair set filled this step (may exceed its room).
    std::uint32_t impulses = 0;
    bool pushes = false;  ///< PGS: a row pushes (the split position pass runs)
    bool bounces = false; ///< PGS: a row may bounce
    bool layers = false;  ///< PGS: moving bodies far apart in mass touch (the layer pass)
    /// The dynamic bodies' mechanical energy after the step (J) and the sum of its terms'
    /// magnitudes (J, the scale of its rounding), when the step summed it (sumBodyEnergy).
    float energy = 0, energyScale = 0;
    /// Whether this step's contacts fit their buffer (particles; SAT's never overflow).
    bool contactsFit() const { return contacts <= capacity; }
};

/// Reserves `bytes` of a per-step buffer with room to grow (half as much again, at least 4 KiB),
/// so that a buffer that grows step by step reallocates now and then, not every step (and
/// Oclgrind, which sees a buffer that replaces one in use as never written, sees few).
Status reserveGrowing(const Context& c, Buffer& b, std::size_t bytes,
                      CallSite where = CallSite::here());

/// The queue, profile and status block the stages of one device world share.
class StageQueue {
  public:
    /// Errors: Device.
    static Result<std::unique_ptr<StageQueue>> create(std::shared_ptr<Context> context);

    const Context& c() const { return *context_; }
    const std::shared_ptr<Context>& sharedContext() const { return context_; }
    Profile& profile() { return profile_; }
    const Profile& profile() const { return profile_; }
    const Buffer& status() const { return status_; }

    /// The global size of a stage whose work-items stride through up to `capacity` items in
    /// groups of `group`: enough groups to fill the device, no more than the items need.
    std::size_t strideItems(std::uint32_t capacity, std::size_t group) const;
    /// Enqueues a copy of `bytes` from `from` to `to` (offsets in bytes), timed.
    Status copy(const Buffer& from, const Buffer& to, std::size_t bytes, std::size_t fromOffset = 0,
                std::size_t toOffset = 0);
    /// Waits until the queue is empty. Errors: Device.
    Status finish();

    /// Clears the status slots at the start of a step (enqueued): the contact capacity is
    /// `capacity` (all ones where contacts cannot overflow).
    Status resetStatus(cl_uint capacity);
    /// Waits for the queue and reads the status block (a blocking read). Errors: Device.
    Result<DeviceStatus> readStatus();
    /// Enqueues the status block's read at the end of a step, with the round's copy, and
    /// flushes the queue.
    Status enqueueStatusRead();
    /// The status block as last read.
    DeviceStatus lastStatus() const;
    /// Enqueues a copy of the status block as it stands (after a collision round's summaries)
    /// into the round's copy, which enqueueStatusRead reads with the block.
    Status keepRoundStatus();
    /// The round's copy as last read.
    DeviceStatus roundStatus() const;
    /// Sets the status block as last read to `st` without reading it: what the host assumes of a
    /// round it does not wait for (the real block arrives with the step's end).
    void assumeStatus(const DeviceStatus& st);
    /// How many times the host has waited for the device (blocking transfers, finish) so far.
    std::uint64_t waits() const { return profile_.waits(); }
    /// Sets one slot, blocking (a test's input, a regrown buffer's capacity). Errors: Device.
    Status writeStatusSlot(std::uint32_t slot, cl_uint value);

  private:
    explicit StageQueue(std::shared_ptr<Context> context) : context_(std::move(context)) {}
    std::shared_ptr<Context> context_;
    Profile profile_;
    Buffer status_;
    // The round's copy of the status block: a buffer of its own, so that no copy has one buffer
    // at both ends.
    Buffer roundStatus_;
    // Host memory of the status block's non-blocking transfers: it stays put until the step is
    // met. statusHost_ holds the block, then the round's copy.
    std::array<cl_uint, RUBBLE_STATUS_COUNT> statusInit_{};
    std::array<cl_uint, 2 * RUBBLE_STATUS_COUNT> statusHost_{};
};

} // namespace rubble::gpu
