// host/gpu/pairs.h: the body pairs of a step on the device and what each keeps for the next
// step (features, impulses): this step's set, last step's, the manifolds, and the carry of the
// still pairs from one to the other. Shared by the SAT collision, the particles with PGS (a
// contact a pair of one point), the PGS solve and the sleep stages.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "host/collision/contact.h"
#include "host/gpu/device_bodies.h"
#include "rubble/shared/hull_contact.h"

namespace rubble::gpu {

/// One step's pairs with what each keeps for the next step.
struct PairSet {
    std::uint32_t capacity = 0; ///< pairs the buffers hold
    /// BodyPairRecord: the step's pairs sorted by (a, b), then (SAT, from the end of the step)
    /// the still pairs carried from the step before (markStillPairs), sorted among themselves.
    Buffer pairs;
    /// Two uints: the pairs found (may exceed capacity), and the entries kept for the next
    /// step's lookups (keptPairsItem: the pairs found and the still pairs carried after them;
    /// 0 in a set that carries nothing, the particles').
    Buffer count;
    Buffer features; ///< PairCache per pair, in pair order
    /// PGS: the contact impulses at the end of the step (PgsImpulse), a pair's `impulseCount`
    /// of them from its `impulseStart`, packed in the order the pairs took their slots
    /// (summarizePairs, carryStillPairs); the next step's rows warm-start from them.
    Buffer impulses, impulseCount, impulseStart;
    std::uint32_t impulseRoom = 0; ///< PgsImpulse slots `impulses` holds
    /// Slots the set's pairs took (the status block's count at the end of the step it was filled
    /// in): at most this many impulses are carried from it into the next set.
    std::uint32_t impulseTotal = 0;
    /// Particles with PGS: each pair's ParticleContactKey (a pair is one contact), in pair order.
    Buffer keys;
};

/// This step's and last step's pairs, and the per-pair arrays of this step.
class PairStore {
  public:
    /// Both sets sized for `guess` pairs (`withKeys`: particle pairs, which carry contact keys),
    /// last step's empty. Errors: Device.
    Status create(StageQueue& q, std::uint32_t guess, bool withKeys);

    PairSet current, previous;
    Buffer found;     ///< the broad phase's candidates, in any order (BodyPairRecord)
    Buffer manifolds; ///< ContactManifold per pair of `current`, in pair order (count 0: none)
    /// Per pair of `current`: its index among last step's entries (collideShapes), their count
    /// when it is new.
    Buffer previousOf;
    Buffer summaries; ///< PGS, per pair: its point count and RUBBLE_PGS_MOVES_* (0: no rows)

    /// Sizes this step's per-pair arrays for `capacity` pairs (last step's keep their size: the
    /// next narrow phase reads them before they change). Errors: Device, Limit.
    Status setCapacity(StageQueue& q, std::uint32_t capacity);
    /// After this round's summaries (`st`, read after them): whether this step's set had room
    /// for the impulses its pairs took. If not, grows the room (the round runs again). If so,
    /// makes room for the impulses the carry may add after them (all of last step's), keeping
    /// those already written. Errors: Device, Limit.
    Result<bool> fitImpulses(StageQueue& q, const DeviceStatus& st);
    /// Before a step that does not wait for its summaries (a step run ahead): room in both sets
    /// for this step's impulses and all of last step's, estimated from last step's round
    /// (`lastRoundImpulses`, the slots its pairs took) with an eighth more; last step's
    /// impulses copied over where its set grows (enqueued). Errors: Device, Limit.
    Status keepImpulseRoomAhead(StageQueue& q, std::uint32_t lastRoundImpulses);
    /// This step's pairs become last step's, at the end of a step; with `carryStill` (SAT) the
    /// still pairs of last step's set (both bodies at rest by `b.jacobi`, holding impulses, not
    /// found again) are carried after them (kernels: markStillPairs to carryStillPairs).
    Status keep(StageQueue& q, const DeviceBodies& b, bool carryStill);

    /// Binds a pair kernel's first arguments: capacity, count (on the device), pairs.
    /// Takes back the swap of the last keep(): the step that kept this set runs again. Only
    /// after a keep that reallocated nothing (both sets of one capacity and impulse room).
    void undoKeep() { std::swap(current, previous); }
    void bindCurrent(Dispatch& d) const;
    void bindPrevious(Dispatch& d) const;
    /// Work-items of a kernel striding through this step's pairs.
    std::size_t strideItems(const StageQueue& q) const;

    /// Replaces this step's pairs (twin tests feed both paths the same pairs); sorted, a < b.
    /// Errors: Device.
    Status upload(StageQueue& q, std::span<const BodyPair> pairs, std::uint32_t bodies);
    /// Reads `count` of this step's pairs, manifolds, features. Errors: Device.
    Result<std::vector<BodyPair>> downloadPairs(StageQueue& q, std::uint32_t count) const;
    Result<std::vector<shared::ContactManifold>> downloadManifolds(StageQueue& q,
                                                                   std::uint32_t count) const;
    Result<std::vector<shared::PairCache>> downloadFeatures(StageQueue& q,
                                                            std::uint32_t count) const;

  private:
    Status carryStillPairs(StageQueue& q, const DeviceBodies& b);
    bool withKeys_ = false;
    // The carry: per entry of last step's set whether it is carried and its place among the
    // carried; per chunk of the set (the sort's work-items) the count and its scan.
    Buffer carry_, place_, chunkCounts_, chunkStarts_;
};

} // namespace rubble::gpu
