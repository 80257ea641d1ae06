// host/gpu/pairs.cpp: the device's pair sets, their sizes, and the carry of still pairs at the
// end of a step (the kernels markStillPairs, placeStillPairs and carryStillPairs).
#include "host/gpu/pairs.h"

#include <algorithm>
#include <string>
#include <utility>

#include "host/core/assert.h"
#include "host/gpu/cl_check.h"
#include "host/gpu/sort.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/particle.h"
#include "rubble/shared/pgs_row.h"

namespace rubble::gpu {
namespace {

// Room for `slots` impulses and an eighth more, so that a pile that grows step by step regrows
// now and then.
std::uint64_t impulseRoomFor(std::uint64_t slots) {
    return std::max<std::uint64_t>(slots + slots / 8, 1024);
}

// A set's impulses in a buffer of `room` slots, the first `keep` copied over (enqueued).
Status growImpulses(StageQueue& q, PairSet& set, std::uint64_t room, std::uint32_t keep) {
    const Context& c = q.c();
    if (room > 0xffffffffu)
        return makeError(ErrorKind::Limit, "device memory",
                         std::to_string(room) + " contact impulses kept for the next step, " +
                             "more than a 32-bit index reaches");
    Buffer grown;
    RUBBLE_TRY(grown.reserve(c.context(), room * sizeof(shared::PgsImpulse)));
    if (keep > 0)
        RUBBLE_CL_CHECK(clEnqueueCopyBuffer(c.queue(), set.impulses.mem(), grown.mem(), 0, 0,
                                            std::size_t(keep) * sizeof(shared::PgsImpulse), 0,
                                            nullptr, nullptr));
    // Released while the copy may be queued: OpenCL keeps it until the copy ran.
    set.impulses = std::move(grown);
    set.impulseRoom = std::uint32_t(room);
    return {};
}

} // namespace

Status PairStore::create(StageQueue& q, std::uint32_t guess, bool withKeys) {
    const Context& c = q.c();
    withKeys_ = withKeys;
    // Last step's set is empty.
    for (PairSet* set : {&current, &previous}) {
        RUBBLE_TRY(set->count.reserve(c.context(), 2 * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, set->count, 0u, 2 * sizeof(cl_uint)));
        RUBBLE_TRY(set->pairs.reserve(c.context(), sizeof(shared::BodyPairRecord)));
        RUBBLE_TRY(set->features.reserve(c.context(), sizeof(shared::PairCache)));
        RUBBLE_TRY(set->impulseCount.reserve(c.context(), sizeof(cl_uint)));
        RUBBLE_TRY(set->impulseStart.reserve(c.context(), sizeof(cl_uint)));
        RUBBLE_TRY(set->impulses.reserve(c.context(), sizeof(shared::PgsImpulse)));
        set->impulseRoom = 1;
        RUBBLE_TRY(set->keys.reserve(c.context(), sizeof(shared::ParticleContactKey)));
    }
    // Particle pairs are one point each and carry nothing: room for a slot per pair never runs
    // out. SAT pairs start with the same and grow by what the summaries take (fitImpulses).
    for (PairSet* set : {&current, &previous})
        RUBBLE_TRY(growImpulses(q, *set, impulseRoomFor(guess), 0));
    // Both sets at the first guess, so that the first steps' swaps reallocate nothing: a buffer
    // released while queued commands still read it is legal, but Oclgrind then sees the buffer
    // that replaces it as never written.
    RUBBLE_TRY(setCapacity(q, guess));
    std::swap(current, previous);
    RUBBLE_TRY(setCapacity(q, guess));
    std::swap(current, previous); // last step's set holds none (its count is 0)
    return {};
}

Status PairStore::setCapacity(StageQueue& q, std::uint32_t capacity) {
    const Context& c = q.c();
    const std::size_t n = capacity;
    current.capacity = capacity;
    RUBBLE_TRY(current.pairs.reserve(c.context(), n * sizeof(shared::BodyPairRecord)));
    RUBBLE_TRY(current.features.reserve(c.context(), n * sizeof(shared::PairCache)));
    RUBBLE_TRY(found.reserve(c.context(), n * sizeof(shared::BodyPairRecord)));
    RUBBLE_TRY(manifolds.reserve(c.context(), n * sizeof(shared::ContactManifold)));
    RUBBLE_TRY(previousOf.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(current.impulseCount.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(current.impulseStart.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(summaries.reserve(c.context(), n * sizeof(cl_uint)));
    if (withKeys_) {
        RUBBLE_TRY(current.keys.reserve(c.context(), n * sizeof(shared::ParticleContactKey)));
        if (current.impulseRoom < capacity)
            RUBBLE_TRY(growImpulses(q, current, impulseRoomFor(capacity), 0));
    }
    return {};
}

Result<bool> PairStore::fitImpulses(StageQueue& q, const DeviceStatus& st) {
    // The carry appends at most every impulse of last step's set after this step's.
    const std::uint64_t need = std::uint64_t(st.impulses) + previous.impulseTotal;
    if (st.impulses > current.impulseRoom) {
        // Some pairs kept nothing: the round runs again with room for all.
        RUBBLE_TRY(growImpulses(q, current, impulseRoomFor(need), 0));
        return false;
    }
    if (need > current.impulseRoom)
        RUBBLE_TRY(growImpulses(q, current, impulseRoomFor(need), st.impulses));
    return true;
}

Status PairStore::keepImpulseRoomAhead(StageQueue& q, std::uint32_t lastRoundImpulses) {
    const std::uint64_t need = std::uint64_t(lastRoundImpulses) + previous.impulseTotal;
    const std::uint64_t room = need + need / 8;
    if (room <= current.impulseRoom && room <= previous.impulseRoom) return {};
    // Both sets alike, so that the step's keep reallocates nothing (PairStore::undoKeep).
    const std::uint64_t grown = impulseRoomFor(room);
    RUBBLE_TRY(growImpulses(q, current, grown, 0));
    return growImpulses(q, previous, grown, previous.impulseTotal);
}

Status PairStore::keep(StageQueue& q, const DeviceBodies& b, bool carryStill) {
    // Particles carry nothing: their sets' second count word stays 0 (keptPairsItem).
    if (carryStill) RUBBLE_TRY(carryStillPairs(q, b));
    std::swap(current, previous);
    // The set to fill next holds as many pairs as the one kept. Growing it (after a pair
    // overflow) reallocates buffers that this step's queued kernels read as last step's: they
    // run first.
    const std::uint32_t capacity = std::max(current.capacity, previous.capacity);
    const bool moreImpulses = previous.impulseRoom > current.impulseRoom;
    if (capacity > current.capacity || moreImpulses) RUBBLE_TRY(q.finish());
    if (moreImpulses) RUBBLE_TRY(growImpulses(q, current, previous.impulseRoom, 0));
    return setCapacity(q, capacity);
}

Status PairStore::carryStillPairs(StageQueue& q, const DeviceBodies& b) {
    const Context& c = q.c();
    const std::uint32_t items = c.workSizes().sortItems;
    const std::size_t entries = std::size_t(previous.capacity) + 1;
    RUBBLE_TRY(carry_.reserve(c.context(), entries * sizeof(cl_uint)));
    RUBBLE_TRY(place_.reserve(c.context(), entries * sizeof(cl_uint)));
    RUBBLE_TRY(chunkCounts_.reserve(c.context(), std::size_t(items) * sizeof(cl_uint)));
    RUBBLE_TRY(chunkStarts_.reserve(c.context(), (std::size_t(items) + 1) * sizeof(cl_uint)));
    const cl_uint previousCapacity = previous.capacity;
    const cl_uint impulseRoom = current.impulseRoom;
    RUBBLE_TRY(Dispatch(c, KernelId::MarkStillPairs, &q.profile())
                   .with([&](Dispatch& d) { bindPrevious(d); })
                   .arg(previous.impulseCount)
                   .with([&](Dispatch& d) { bindCurrent(d); })
                   .arg(b.jacobi)
                   .arg(carry_)
                   .arg(chunkCounts_)
                   .arg(q.status())
                   .run(items, RUBBLE_GROUP_SCAN));
    RUBBLE_TRY(exclusiveScan(q, chunkCounts_, chunkStarts_, items));
    RUBBLE_TRY(Dispatch(c, KernelId::PlaceStillPairs, &q.profile())
                   .arg(previousCapacity)
                   .arg(previous.count)
                   .arg(carry_)
                   .arg(chunkStarts_)
                   .arg(place_)
                   .run(items, RUBBLE_GROUP_SCAN));
    const std::size_t group = c.workSizes().pairGroup;
    return Dispatch(c, KernelId::CarryStillPairs, &q.profile())
        .with([&](Dispatch& d) { bindPrevious(d); })
        .arg(previous.impulseCount)
        .arg(previous.impulseStart)
        .arg(previous.impulses)
        .arg(carry_)
        .arg(place_)
        .with([&](Dispatch& d) { bindCurrent(d); })
        .arg(current.impulseCount)
        .arg(current.impulseStart)
        .arg(impulseRoom)
        .arg(current.impulses)
        .arg(q.status())
        .run(q.strideItems(previous.capacity, group), group);
}

void PairStore::bindCurrent(Dispatch& d) const {
    const cl_uint capacity = current.capacity;
    d.arg(capacity).arg(current.count).arg(current.pairs);
}

void PairStore::bindPrevious(Dispatch& d) const {
    const cl_uint capacity = previous.capacity;
    d.arg(capacity).arg(previous.count).arg(previous.pairs);
}

std::size_t PairStore::strideItems(const StageQueue& q) const {
    return q.strideItems(current.capacity, q.c().workSizes().pairGroup);
}

Status PairStore::upload(StageQueue& q, std::span<const BodyPair> pairs, std::uint32_t bodies) {
    const Context& c = q.c();
    if (pairs.size() > current.capacity) RUBBLE_TRY(setCapacity(q, std::uint32_t(pairs.size())));
    std::vector<shared::BodyPairRecord> records;
    records.reserve(pairs.size());
    for (const BodyPair& p : pairs) {
        RUBBLE_ASSERT(p.a < p.b && p.b < bodies);
        records.push_back({p.a, p.b});
    }
    RUBBLE_TRY(gpu::upload(c, current.pairs, records));
    const cl_uint count = cl_uint(pairs.size());
    RUBBLE_TRY(gpu::upload(c, current.count, std::span<const cl_uint>(&count, 1)));
    return q.writeStatusSlot(RUBBLE_STATUS_PAIRS, count);
}

Result<std::vector<BodyPair>> PairStore::downloadPairs(StageQueue& q, std::uint32_t count) const {
    const Result<std::vector<shared::BodyPairRecord>> records =
        download<shared::BodyPairRecord>(q.c(), current.pairs, std::min(count, current.capacity));
    RUBBLE_TRY(records);
    std::vector<BodyPair> pairs;
    pairs.reserve(records->size());
    for (const shared::BodyPairRecord& r : *records) pairs.push_back(BodyPair{r.a, r.b});
    return pairs;
}

Result<std::vector<shared::ContactManifold>>
PairStore::downloadManifolds(StageQueue& q, std::uint32_t count) const {
    return download<shared::ContactManifold>(q.c(), manifolds, std::min(count, current.capacity));
}

Result<std::vector<shared::PairCache>> PairStore::downloadFeatures(StageQueue& q,
                                                                   std::uint32_t count) const {
    return download<shared::PairCache>(q.c(), current.features, std::min(count, current.capacity));
}

} // namespace rubble::gpu
