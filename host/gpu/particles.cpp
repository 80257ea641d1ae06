// host/gpu/particles.cpp: dispatch of the particle method (kernels/particles.cl, grid.cl). The
// CPU twins are in host/collision/particles.cpp and grid.cpp. Argument order is the kernel
// signature's.
#include "host/gpu/particles.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "host/core/limits.h"
#include "rubble/shared/contact_row.h"

namespace rubble::gpu {

Status ParticleCollision::create(StageQueue& q, const ParticleSet* set, BodiesView bodyArrays,
                                 PairStore* pairs, std::uint32_t capacity) {
    const Context& c = q.c();
    pairs_ = pairs;
    const ParticleSet empty;
    const ParticleSet& p = set ? *set : empty;
    count_ = std::uint32_t(p.particles.size());
    staticCount_ = std::uint32_t(p.statics.size());
    bits_ = p.bits;
    cellSize_ = p.cellSize;
    margin_ = p.margin;
    RUBBLE_TRY(upload(c, records_, std::span(p.particles)));
    RUBBLE_TRY(upload(c, statics_, std::span(p.statics)));
    const std::size_t n = count_, words = n * sizeof(cl_uint);
    RUBBLE_TRY(world_.reserve(c.context(), n * sizeof(shared::float4)));
    RUBBLE_TRY(sortedWorld_.reserve(c.context(), n * sizeof(shared::float4)));
    for (Buffer* b : {&keys_, &values_, &keysAlt_, &valuesAlt_, &sortedTags_, &contacts_.head})
        RUBBLE_TRY(b->reserve(c.context(), words));
    const std::size_t cells = std::size_t(1) << bits_;
    RUBBLE_TRY(cellFirst_.reserve(c.context(), (cells + 1) * sizeof(cl_uint)));
    // Particles of bodies asleep at upload keep these positions until they wake.
    std::vector<shared::float4> world(n);
    rubble::transformParticles(p.particles, bodyArrays.poses, world);
    RUBBLE_TRY(upload(c, world_, world));

    // Per-body lists.
    const std::size_t bodies = bodyArrays.count();
    RUBBLE_TRY(contacts_.bodyCount.reserve(c.context(), bodies * sizeof(cl_uint)));
    RUBBLE_TRY(contacts_.bodyStart.reserve(c.context(), (bodies + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(contacts_.cursor.reserve(c.context(), (bodies + 1) * sizeof(cl_uint)));
    // Last step's contacts: none yet, but bound by every step.
    for (Buffer* b : {&contacts_.next, &contacts_.previous, &contacts_.previousRows})
        RUBBLE_TRY(b->reserve(c.context(), 16));
    // A first guess of the contacts: a few per particle; it grows when a step needs more.
    const std::uint32_t guess = capacity > 0 ? capacity : std::max<std::uint32_t>(1024, 2 * count_);
    if (pairs_) RUBBLE_TRY(pairs_->create(q, guess, true));
    return setCapacity(q, guess);
}

Status ParticleCollision::setCapacity(StageQueue& q, std::uint32_t capacity) {
    const Context& c = q.c();
    contacts_.capacity = capacity;
    const std::size_t n = capacity;
    RUBBLE_TRY(contacts_.contacts.reserve(c.context(), n * sizeof(shared::ParticleContact)));
    RUBBLE_TRY(contacts_.unsorted.reserve(c.context(), n * sizeof(shared::ParticleContact)));
    RUBBLE_TRY(contacts_.rows.reserve(c.context(), n * sizeof(shared::ContactRow)));
    RUBBLE_TRY(contacts_.impulses.reserve(c.context(), n * sizeof(shared::float4)));
    RUBBLE_TRY(contacts_.bodyList.reserve(c.context(), 2 * n * sizeof(cl_uint)));
    RUBBLE_TRY(contacts_.arms.reserve(c.context(), 2 * n * sizeof(shared::float4)));
    for (Buffer* b : {&contacts_.sortKeys, &contacts_.sortValues, &contacts_.sortKeysAlt,
                      &contacts_.sortValuesAlt})
        RUBBLE_TRY(b->reserve(c.context(), n * sizeof(cl_uint)));
    // Last step's contacts keep their size: the next step reads them before they change. With
    // PGS each contact is a pair.
    if (pairs_ && pairs_->current.capacity < capacity) RUBBLE_TRY(pairs_->setCapacity(q, capacity));
    return {};
}

Status ParticleCollision::grow(StageQueue& q, const DeviceStatus& st, std::int64_t step,
                               const char* again) {
    const std::size_t budget = particleContactBudget(count_);
    if (st.contacts > budget)
        return limitError("collideParticles", "particle contacts", st.contacts, budget, step,
                          "bodies overlap each other in large numbers");
    const auto grown = std::uint32_t(std::min<std::size_t>(st.contacts + st.contacts / 2, budget));
    std::fprintf(stderr,
                 "rubble: contact overflow (%u contacts, room for %u): buffer grown to %u and %s "
                 "run again\n",
                 st.contacts, st.capacity, grown, again);
    RUBBLE_TRY(setCapacity(q, grown));
    RUBBLE_TRY(q.writeStatusSlot(RUBBLE_STATUS_CONTACTS, 0u));
    return q.writeStatusSlot(RUBBLE_STATUS_CAPACITY, contacts_.capacity);
}

Status ParticleCollision::readCount(StageQueue& q) {
    for (;;) {
        Result<DeviceStatus> st = q.readStatus();
        RUBBLE_TRY(st);
        if (st->contactsFit()) {
            contacts_.count = st->contacts;
            return {};
        }
        RUBBLE_TRY(grow(q, *st, 0, "the stage"));
        RUBBLE_TRY(collide(q));
    }
}

Status ParticleCollision::keepForWarmStart(StageQueue& q) {
    std::swap(contacts_.contacts, contacts_.previous);
    std::swap(contacts_.rows, contacts_.previousRows);
    kept_ = true;
    // The swapped-in buffers must still hold a full step.
    return setCapacity(q, contacts_.capacity);
}

void ParticleCollision::undoKeep() {
    if (!kept_) return;
    std::swap(contacts_.contacts, contacts_.previous);
    std::swap(contacts_.rows, contacts_.previousRows);
    kept_ = false;
}

Status ParticleCollision::uploadContacts(StageQueue& q,
                                         std::span<const shared::ParticleContact> contacts) {
    if (contacts.size() > contacts_.capacity)
        RUBBLE_TRY(setCapacity(q, std::uint32_t(contacts.size())));
    contacts_.count = std::uint32_t(contacts.size());
    RUBBLE_TRY(upload(q.c(), contacts_.contacts, contacts));
    // The stages read the count from the status block.
    RUBBLE_TRY(q.writeStatusSlot(RUBBLE_STATUS_CONTACTS, contacts_.count));
    RUBBLE_TRY(q.writeStatusSlot(RUBBLE_STATUS_CAPACITY, contacts_.capacity));
    return q.finish();
}

Status ParticleCollision::transform(StageQueue& q, const DeviceBodies& b) {
    const cl_uint count = count_;
    return Dispatch(q.c(), KernelId::TransformParticles, &q.profile())
        .arg(count)
        .arg(records_)
        .arg(b.poses)
        .arg(b.flags)
        .arg(world_)
        .run(count, RUBBLE_GROUP_PARTICLES); // no host copy: buildGrid reads the world
}

Status ParticleCollision::buildGrid(StageQueue& q, const DeviceBodies& b, RadixSort& sort) {
    const cl_uint count = count_, bits = bits_;
    const cl_float inverseCellSize = 1.0f / cellSize_;
    RUBBLE_TRY(Dispatch(q.c(), KernelId::ComputeCellKeys, &q.profile())
                   .arg(count)
                   .arg(inverseCellSize)
                   .arg(bits)
                   .arg(world_)
                   .arg(keys_)
                   .arg(values_)
                   .run(count, RUBBLE_GROUP_PARTICLES));
    RUBBLE_TRY(sort.sort(q, keys_, values_, keysAlt_, valuesAlt_, count, bits));
    const cl_uint cells = cl_uint(1) << bits;
    // No particles: every cell starts (and ends) at slot 0.
    if (count == 0)
        return fill(q.c(), cellFirst_, 0u, (std::size_t(cells) + 1) * sizeof(cl_uint),
                    &q.profile());
    return Dispatch(q.c(), KernelId::FindCellRanges, &q.profile())
        .arg(count)
        .arg(cells)
        .arg(keys_)
        .arg(values_)
        .arg(world_)
        .arg(records_)
        .arg(b.flags)
        .arg(cellFirst_)
        .arg(sortedWorld_)
        .arg(sortedTags_)
        .run(count, RUBBLE_GROUP_PARTICLES);
}

Status ParticleCollision::collide(StageQueue& q) {
    const cl_uint count = count_, statics = staticCount_;
    const cl_float inverseCellSize = 1.0f / cellSize_;
    const cl_uint bits = bits_;
    const cl_float margin = margin_;
    return Dispatch(q.c(), KernelId::CollideParticles, &q.profile())
        .arg(count)
        .arg(statics)
        .arg(inverseCellSize)
        .arg(bits)
        .arg(margin)
        .arg(cellFirst_)
        .arg(sortedWorld_)
        .arg(sortedTags_)
        .arg(values_)
        .arg(statics_)
        .arg(contacts_.contacts)
        .arg(q.status())
        .run(count, RUBBLE_GROUP_PARTICLES);
}

Status ParticleCollision::sortContacts(StageQueue& q, RadixSort& sort, std::uint32_t bodies,
                                       bool byPair) {
    const cl_uint capacity = contacts_.capacity;
    const std::size_t items = q.strideItems(contacts_.capacity, RUBBLE_GROUP_CONTACTS);
    auto bitsFor = [](std::uint64_t values) {
        std::uint32_t bits = 1;
        while (bits < 32 && (std::uint64_t(1) << bits) < values) ++bits;
        return bits;
    };
    // Stable passes from the last field of the order to its first: (particleA, featureB), which
    // names a contact, and before it, for PGS, the pair (lower, higher body).
    const std::uint32_t featureBits = bitsFor(std::uint64_t(count_) + staticCount_);
    const std::uint32_t particleBits = bitsFor(count_);
    const std::uint32_t bodyBits = bitsFor(bodies);
    const cl_uint passes = byPair ? 4u : 2u;
    ContactBuffers& k = contacts_;
    for (cl_uint field = RUBBLE_CONTACT_KEY_FEATURE; field < passes; ++field) {
        // A pass after the first reads the last one's order; keys and values are then written
        // afresh.
        if (field != RUBBLE_CONTACT_KEY_FEATURE) std::swap(k.sortValues, k.sortKeysAlt);
        RUBBLE_TRY(Dispatch(q.c(), KernelId::ContactKeys, &q.profile())
                       .arg(q.status())
                       .arg(k.contacts)
                       .arg(k.sortKeysAlt)
                       .arg(field)
                       .arg(k.sortKeys)
                       .arg(k.sortValues)
                       .run(items, RUBBLE_GROUP_CONTACTS));
        const std::uint32_t bits = field == RUBBLE_CONTACT_KEY_FEATURE    ? featureBits
                                   : field == RUBBLE_CONTACT_KEY_PARTICLE ? particleBits
                                                                          : bodyBits;
        RUBBLE_TRY(sort.sort(q, k.sortKeys, k.sortValues, k.sortKeysAlt, k.sortValuesAlt, capacity,
                             bits, RUBBLE_STATUS_CONTACTS));
    }
    std::swap(k.contacts, k.unsorted);
    return Dispatch(q.c(), KernelId::PermuteContacts, &q.profile())
        .arg(q.status())
        .arg(k.sortValues)
        .arg(k.unsorted)
        .arg(k.contacts)
        .run(items, RUBBLE_GROUP_CONTACTS);
}

Status ParticleCollision::toPairs(StageQueue& q, PairStore& pairs) {
    const cl_uint previousCapacity = pairs.previous.capacity;
    return Dispatch(q.c(), KernelId::ParticlePairs, &q.profile())
        .arg(q.status())
        .arg(contacts_.contacts)
        .arg(previousCapacity)
        .arg(pairs.previous.count)
        .arg(pairs.previous.keys)
        .arg(pairs.current.count)
        .arg(pairs.current.pairs)
        .arg(pairs.manifolds)
        .arg(pairs.current.keys)
        .arg(pairs.previousOf)
        .run(q.strideItems(contacts_.capacity, RUBBLE_GROUP_CONTACTS), RUBBLE_GROUP_CONTACTS);
}

} // namespace rubble::gpu
