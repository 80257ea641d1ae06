// host/gpu/particles.cpp: dispatch of OpenCL stages 2 and 4 (kernels/particles.cl):
// transformParticles and collideParticles with its contact buffer. The CPU twins are in
// host/collision/particle_world.cpp. Argument order is the kernel signature's.
#include <algorithm>
#include <cstdio>

#include "host/gpu/pipeline.h"
#include "host/world/world_state.h"

namespace rubble::gpu {

Status Pipeline::uploadParticles(const WorldState& s) {
    const Context& c = *context_;
    const ParticleState& p = s.particles;
    particles_.count = std::uint32_t(p.particles.size());
    particles_.staticCount = std::uint32_t(p.statics.size());
    particles_.bits = p.bits;
    particles_.cellSize = p.cellSize;
    RUBBLE_TRY(upload(c, particles_.records, std::span(p.particles)));
    RUBBLE_TRY(upload(c, particles_.statics, std::span(p.statics)));
    const std::size_t n = particles_.count, words = n * sizeof(cl_uint);
    RUBBLE_TRY(particles_.world.reserve(c.context(), n * sizeof(shared::float4)));
    for (Buffer* b : {&particles_.keys, &particles_.values, &particles_.keysAlt,
                      &particles_.valuesAlt, &contacts_.head})
        RUBBLE_TRY(b->reserve(c.context(), words));
    const std::size_t histogram = RUBBLE_SORT_BUCKETS * RUBBLE_SORT_ITEMS;
    RUBBLE_TRY(particles_.histogram.reserve(c.context(), histogram * sizeof(cl_uint)));
    RUBBLE_TRY(particles_.offsets.reserve(c.context(), (histogram + 1) * sizeof(cl_uint)));
    const std::size_t cells = std::size_t(1) << particles_.bits;
    RUBBLE_TRY(particles_.cellStart.reserve(c.context(), cells * sizeof(cl_uint)));
    RUBBLE_TRY(particles_.cellEnd.reserve(c.context(), cells * sizeof(cl_uint)));

    // Per-body lists and surfaces.
    const std::size_t bodies = s.bodyCount();
    RUBBLE_TRY(contacts_.bodyCount.reserve(c.context(), bodies * sizeof(cl_uint)));
    RUBBLE_TRY(contacts_.bodyStart.reserve(c.context(), (bodies + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(contacts_.cursor.reserve(c.context(), (bodies + 1) * sizeof(cl_uint)));
    const std::vector<shared::float4> surfaces = bodySurfaces(s);
    RUBBLE_TRY(upload(c, contacts_.surfaces, std::span(surfaces)));
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
    RUBBLE_TRY(contacts_.bodyList.reserve(c.context(), 2 * n * sizeof(cl_uint)));
    for (Buffer* b : {&contacts_.sortKeys, &contacts_.sortValues, &contacts_.sortKeysAlt,
                      &contacts_.sortValuesAlt})
        RUBBLE_TRY(b->reserve(c.context(), n * sizeof(cl_uint)));
    // Last step's contacts keep their size: the next step reads them before they change.
    return {};
}

Status Pipeline::uploadContacts(std::span<const shared::ParticleContact> contacts) {
    if (contacts.size() > contacts_.capacity)
        RUBBLE_TRY(setContactCapacity(std::uint32_t(contacts.size()), contacts_.growable));
    contacts_.count = std::uint32_t(contacts.size());
    return upload(*context_, contacts_.contacts, contacts);
}

Status Pipeline::transformParticles() {
    const cl_uint count = particles_.count;
    return Dispatch(*context_, KernelId::TransformParticles)
        .arg(count)
        .arg(particles_.records)
        .arg(bodies_.poses)
        .arg(particles_.world)
        .run(count, RUBBLE_GROUP_PARTICLES); // no host copy: buildGrid reads the world
}

Status Pipeline::collideParticles() {
    const cl_uint count = particles_.count, statics = particles_.staticCount;
    const cl_float inverseCellSize = 1.0f / particles_.cellSize;
    const cl_uint bits = particles_.bits;
    for (;;) {
        const cl_uint capacity = contacts_.capacity;
        RUBBLE_TRY(Dispatch(*context_, KernelId::CollideParticles)
                       .arg(count)
                       .arg(statics)
                       .arg(inverseCellSize)
                       .arg(bits)
                       .arg(capacity)
                       .arg(particles_.values)
                       .arg(particles_.cellStart)
                       .arg(particles_.cellEnd)
                       .arg(particles_.world)
                       .arg(particles_.records)
                       .arg(bodies_.masses)
                       .arg(particles_.statics)
                       .arg(contacts_.contacts)
                       .arg(status_)
                       .run(count, RUBBLE_GROUP_PARTICLES));
        // The contact count decides the size of every later dispatch: the host reads it.
        Result<DeviceStatus> st = readStatus();
        RUBBLE_TRY(st);
        if (st->contacts <= capacity) {
            contacts_.count = st->contacts;
            return {};
        }
        if (!contacts_.growable)
            return makeError(ErrorKind::Numerical, "collideParticles",
                             "contact overflow: " + std::to_string(st->contacts) +
                                 " contacts do not fit the buffer of " +
                                 std::to_string(capacity));
        const std::uint32_t grown = st->contacts + st->contacts / 2;
        std::fprintf(stderr, "rubble: contact overflow (%u contacts, room for %u): buffer grown "
                             "to %u and the stage run again\n",
                     st->contacts, capacity, grown);
        RUBBLE_TRY(setContactCapacity(grown, true));
        const cl_uint zero = 0;
        RUBBLE_CL_CHECK(clEnqueueWriteBuffer(context_->queue(), status_.mem(), CL_TRUE,
                                             RUBBLE_STATUS_CONTACTS * sizeof(cl_uint),
                                             sizeof zero, &zero, 0, nullptr, nullptr));
    }
}

Status Pipeline::sortContacts() {
    const cl_uint count = contacts_.count;
    if (count == 0) return {};
    RUBBLE_TRY(Dispatch(*context_, KernelId::ContactKeys)
                   .arg(count)
                   .arg(contacts_.contacts)
                   .arg(contacts_.sortKeys)
                   .arg(contacts_.sortValues)
                   .run(count, RUBBLE_GROUP_CONTACTS));
    std::uint32_t bits = 1;
    while (bits < 32 && (std::uint64_t(1) << bits) < particles_.count) ++bits;
    RUBBLE_TRY(radixSort(contacts_.sortKeys, contacts_.sortValues, contacts_.sortKeysAlt,
                         contacts_.sortValuesAlt, count, bits));
    std::swap(contacts_.contacts, contacts_.unsorted);
    return Dispatch(*context_, KernelId::PermuteContacts)
        .arg(count)
        .arg(contacts_.sortValues)
        .arg(contacts_.unsorted)
        .arg(contacts_.contacts)
        .run(count, RUBBLE_GROUP_CONTACTS);
}

} // namespace rubble::gpu
