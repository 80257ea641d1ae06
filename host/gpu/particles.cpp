// host/gpu/particles.cpp: dispatch of OpenCL stages 2 and 4 (kernels/particles.cl):
// transformParticles and collideParticles with its contact buffer. The CPU twins are in
// host/collision/particles.cpp. Argument order is the kernel signature's.
#include <algorithm>
#include <cstdio>

#include "host/collision/particles.h"
#include "host/core/limits.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::uploadParticles(const ParticleSet* set, BodiesView bodyArrays,
                                 std::span<const shared::float4> surfaces) {
    const Context& c = *context_;
    const ParticleSet empty;
    const ParticleSet& p = set ? *set : empty;
    particles_.count = std::uint32_t(p.particles.size());
    particles_.staticCount = std::uint32_t(p.statics.size());
    particles_.bits = p.bits;
    particles_.cellSize = p.cellSize;
    particles_.margin = p.margin;
    RUBBLE_TRY(upload(c, particles_.records, std::span(p.particles)));
    RUBBLE_TRY(upload(c, particles_.statics, std::span(p.statics)));
    const std::size_t n = particles_.count, words = n * sizeof(cl_uint);
    RUBBLE_TRY(particles_.world.reserve(c.context(), n * sizeof(shared::float4)));
    RUBBLE_TRY(particles_.sortedWorld.reserve(c.context(), n * sizeof(shared::float4)));
    for (Buffer* b : {&particles_.keys, &particles_.values, &particles_.keysAlt,
                      &particles_.valuesAlt, &particles_.sortedTags, &contacts_.head})
        RUBBLE_TRY(b->reserve(c.context(), words));
    const std::size_t histogram = RUBBLE_SORT_BUCKETS * c.workSizes().sortItems;
    RUBBLE_TRY(particles_.histogram.reserve(c.context(), histogram * sizeof(cl_uint)));
    RUBBLE_TRY(particles_.offsets.reserve(c.context(), (histogram + 1) * sizeof(cl_uint)));
    const std::size_t cells = std::size_t(1) << particles_.bits;
    RUBBLE_TRY(particles_.cellFirst.reserve(c.context(), (cells + 1) * sizeof(cl_uint)));
    // Particles of bodies asleep at upload keep these positions until they wake.
    std::vector<shared::float4> world(n);
    rubble::transformParticles(p.particles, bodyArrays.poses, world);
    RUBBLE_TRY(upload(c, particles_.world, world));

    // Per-body lists and surfaces.
    const std::size_t bodies = bodyArrays.count();
    RUBBLE_TRY(contacts_.bodyCount.reserve(c.context(), bodies * sizeof(cl_uint)));
    RUBBLE_TRY(contacts_.bodyStart.reserve(c.context(), (bodies + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(contacts_.cursor.reserve(c.context(), (bodies + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(upload(c, contacts_.surfaces, surfaces));
    // Last step's contacts: none yet, but bound by every step.
    for (Buffer* b : {&contacts_.next, &contacts_.previous, &contacts_.previousRows})
        RUBBLE_TRY(b->reserve(c.context(), 16));
    // A first guess of the contacts: a few per particle; it grows when a step needs more.
    return setContactCapacity(std::max<std::uint32_t>(1024, 2 * particles_.count), true);
}

Status Pipeline::setContactCapacity(std::uint32_t capacity, bool growable) {
    const Context& c = *context_;
    contacts_.capacity = capacity;
    contacts_.growable = growable;
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
    if (particlePgs_ && sat_.current.capacity < capacity) RUBBLE_TRY(setPairCapacity(capacity));
    return {};
}

Status Pipeline::uploadContacts(std::span<const shared::ParticleContact> contacts) {
    if (contacts.size() > contacts_.capacity)
        RUBBLE_TRY(setContactCapacity(std::uint32_t(contacts.size()), contacts_.growable));
    contacts_.count = std::uint32_t(contacts.size());
    RUBBLE_TRY(upload(*context_, contacts_.contacts, contacts));
    // The stages read the count from the status block.
    statusHost_[RUBBLE_STATUS_CONTACTS] = contacts_.count;
    statusHost_[RUBBLE_STATUS_CAPACITY] = contacts_.capacity;
    RUBBLE_TRY(upload(*context_, status_, std::span<const cl_uint>(statusHost_)));
    return finish();
}

Status Pipeline::transformParticles() {
    const cl_uint count = particles_.count;
    return Dispatch(*context_, KernelId::TransformParticles, &profile_)
        .arg(count)
        .arg(particles_.records)
        .arg(bodies_.poses)
        .arg(bodies_.flags)
        .arg(particles_.world)
        .run(count, RUBBLE_GROUP_PARTICLES); // no host copy: buildGrid reads the world
}

Status Pipeline::collideParticles() {
    const cl_uint count = particles_.count, statics = particles_.staticCount;
    const cl_float inverseCellSize = 1.0f / particles_.cellSize;
    const cl_uint bits = particles_.bits;
    const cl_float margin = particles_.margin;
    return Dispatch(*context_, KernelId::CollideParticles, &profile_)
        .arg(count)
        .arg(statics)
        .arg(inverseCellSize)
        .arg(bits)
        .arg(margin)
        .arg(particles_.cellFirst)
        .arg(particles_.sortedWorld)
        .arg(particles_.sortedTags)
        .arg(particles_.values)
        .arg(particles_.statics)
        .arg(contacts_.contacts)
        .arg(status_)
        .run(count, RUBBLE_GROUP_PARTICLES);
}

Status Pipeline::growContacts(const DeviceStatus& st, std::int64_t step, const char* again) {
    if (!contacts_.growable)
        return makeError(ErrorKind::Numerical, "collideParticles",
                         "contact overflow: " + std::to_string(st.contacts) +
                             " contacts do not fit the buffer of " + std::to_string(st.capacity));
    const std::size_t budget = particleContactBudget(particles_.count);
    if (st.contacts > budget)
        return limitError("collideParticles", "particle contacts", st.contacts, budget, step,
                          "bodies overlap each other in large numbers");
    const auto grown = std::uint32_t(std::min<std::size_t>(st.contacts + st.contacts / 2, budget));
    std::fprintf(stderr,
                 "rubble: contact overflow (%u contacts, room for %u): buffer grown to %u and %s "
                 "run again\n",
                 st.contacts, st.capacity, grown, again);
    RUBBLE_TRY(setContactCapacity(grown, true));
    RUBBLE_TRY(writeStatusSlot(RUBBLE_STATUS_CONTACTS, 0u));
    return writeStatusSlot(RUBBLE_STATUS_CAPACITY, contacts_.capacity);
}

Status Pipeline::readContactCount() {
    for (;;) {
        Result<DeviceStatus> st = readStatus();
        RUBBLE_TRY(st);
        if (st->contacts <= st->capacity) {
            contacts_.count = st->contacts;
            return {};
        }
        RUBBLE_TRY(growContacts(*st, 0, "the stage"));
        RUBBLE_TRY(collideParticles());
    }
}

Status Pipeline::sortContacts(bool byPair) {
    const cl_uint capacity = contacts_.capacity;
    auto bitsFor = [](std::uint64_t values) {
        std::uint32_t bits = 1;
        while (bits < 32 && (std::uint64_t(1) << bits) < values) ++bits;
        return bits;
    };
    // Stable passes from the last field of the order to its first: (particleA, featureB), which
    // names a contact, and before it, for PGS, the pair (lower, higher body).
    const std::uint32_t featureBits = bitsFor(std::uint64_t(particles_.count) +
                                              particles_.staticCount);
    const std::uint32_t particleBits = bitsFor(particles_.count);
    const std::uint32_t bodyBits = bitsFor(bodies_.count);
    const cl_uint passes = byPair ? 4u : 2u;
    for (cl_uint field = RUBBLE_CONTACT_KEY_FEATURE; field < passes; ++field) {
        // A pass after the first reads the last one's order; keys and values are then written
        // afresh.
        if (field != RUBBLE_CONTACT_KEY_FEATURE)
            std::swap(contacts_.sortValues, contacts_.sortKeysAlt);
        RUBBLE_TRY(Dispatch(*context_, KernelId::ContactKeys, &profile_)
                       .arg(status_)
                       .arg(contacts_.contacts)
                       .arg(contacts_.sortKeysAlt)
                       .arg(field)
                       .arg(contacts_.sortKeys)
                       .arg(contacts_.sortValues)
                       .run(strideItems(), RUBBLE_GROUP_CONTACTS));
        const std::uint32_t bits = field == RUBBLE_CONTACT_KEY_FEATURE    ? featureBits
                                   : field == RUBBLE_CONTACT_KEY_PARTICLE ? particleBits
                                                                          : bodyBits;
        RUBBLE_TRY(radixSort(contacts_.sortKeys, contacts_.sortValues, contacts_.sortKeysAlt,
                             contacts_.sortValuesAlt, capacity, bits, RUBBLE_STATUS_CONTACTS));
    }
    std::swap(contacts_.contacts, contacts_.unsorted);
    return Dispatch(*context_, KernelId::PermuteContacts, &profile_)
        .arg(status_)
        .arg(contacts_.sortValues)
        .arg(contacts_.unsorted)
        .arg(contacts_.contacts)
        .run(strideItems(), RUBBLE_GROUP_CONTACTS);
}

Status Pipeline::particlePairs() {
    const SatBuffers& s = sat_;
    const cl_uint previousCapacity = s.previous.capacity;
    return Dispatch(*context_, KernelId::ParticlePairs, &profile_)
        .arg(status_)
        .arg(contacts_.contacts)
        .arg(previousCapacity)
        .arg(s.previous.count)
        .arg(s.previous.keys)
        .arg(s.current.count)
        .arg(s.current.pairs)
        .arg(s.manifolds)
        .arg(s.current.keys)
        .arg(s.previousOf)
        .run(strideItems(), RUBBLE_GROUP_CONTACTS);
}

} // namespace rubble::gpu
