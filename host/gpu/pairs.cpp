// host/gpu/pairs.cpp: the device's pair sets, their sizes, and the carry of still pairs at the
// end of a step (the kernels markStillPairs, placeStillPairs and carryStillPairs).
#include "host/gpu/pairs.h"

#include <algorithm>
#include <utility>

#include "host/core/assert.h"
#include "host/gpu/sort.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/particle.h"
#include "rubble/shared/pgs_row.h"

namespace rubble::gpu {

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
        RUBBLE_TRY(set->impulses.reserve(c.context(), 4 * sizeof(shared::PgsImpulse)));
        RUBBLE_TRY(set->keys.reserve(c.context(), sizeof(shared::ParticleContactKey)));
    }
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
    RUBBLE_TRY(current.impulses.reserve(c.context(), 4 * n * sizeof(shared::PgsImpulse)));
    RUBBLE_TRY(summaries.reserve(c.context(), n * sizeof(cl_uint)));
    if (withKeys_)
        RUBBLE_TRY(current.keys.reserve(c.context(), n * sizeof(shared::ParticleContactKey)));
    return {};
}

Status PairStore::keep(StageQueue& q, const DeviceBodies& b, bool carryStill) {
    // Particles carry nothing: their sets' second count word stays 0 (keptPairsItem).
    if (carryStill) RUBBLE_TRY(carryStillPairs(q, b));
    std::swap(current, previous);
    // The set to fill next holds as many pairs as the one kept. Growing it (after a pair
    // overflow) reallocates buffers that this step's queued kernels read as last step's: they
    // run first.
    const std::uint32_t capacity = std::max(current.capacity, previous.capacity);
    if (capacity > current.capacity) RUBBLE_TRY(q.finish());
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
        .arg(previous.impulses)
        .arg(carry_)
        .arg(place_)
        .with([&](Dispatch& d) { bindCurrent(d); })
        .arg(current.impulseCount)
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
