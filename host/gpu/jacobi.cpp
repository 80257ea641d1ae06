// host/gpu/jacobi.cpp: dispatch of OpenCL stage 5, solveJacobi (kernels/jacobi.cl): per-body
// row lists, warm start from last step's contacts, rows, the iterations, and the impulses on the
// host's bodies. The CPU twins are in host/dynamics/jacobi.cpp. Argument order is the kernel
// signature's; stages over contacts stride through the count the status block holds.
#include <utility>

#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::prepareJacobiBodies() {
    const cl_uint bodies = bodies_.count;
    return Dispatch(*context_, KernelId::PrepareJacobiBodies, &profile_)
        .arg(bodies)
        .arg(bodies_.masses)
        .arg(bodies_.flags)
        .arg(bodies_.poses)
        .arg(bodies_.jacobi)
        .run(bodies, RUBBLE_GROUP_BODIES);
}

Status Pipeline::buildJacobiRows(const shared::SolverParams& params, bool warmStart) {
    const Context& c = *context_;
    const cl_uint bodies = bodies_.count;
    RUBBLE_TRY(prepareJacobiBodies());
    // Per-body lists: count, scan, fill, then each list in row order.
    RUBBLE_TRY(fill(c, contacts_.bodyCount, 0u, bodies * sizeof(cl_uint), &profile_));
    RUBBLE_TRY(Dispatch(c, KernelId::CountBodyContacts, &profile_)
                   .arg(status_)
                   .arg(contacts_.contacts)
                   .arg(bodies_.flags)
                   .arg(contacts_.bodyCount)
                   .run(strideItems(), RUBBLE_GROUP_CONTACTS));
    RUBBLE_TRY(exclusiveScan(contacts_.bodyCount, contacts_.bodyStart, bodies));
    const std::size_t listBytes = (bodies + 1) * sizeof(cl_uint);
    RUBBLE_CL_CHECK(clEnqueueCopyBuffer(c.queue(), contacts_.bodyStart.mem(),
                                        contacts_.cursor.mem(), 0, 0, listBytes, 0, nullptr,
                                        profile_.transfer(Transfer::Copy, listBytes)));
    RUBBLE_TRY(Dispatch(c, KernelId::FillBodyLists, &profile_)
                   .arg(status_)
                   .arg(contacts_.contacts)
                   .arg(bodies_.flags)
                   .arg(contacts_.cursor)
                   .arg(contacts_.bodyList)
                   .run(strideItems(), RUBBLE_GROUP_CONTACTS));
    RUBBLE_TRY(Dispatch(c, KernelId::SortBodyLists, &profile_)
                   .arg(bodies)
                   .arg(contacts_.bodyStart)
                   .arg(contacts_.bodyList)
                   .run(bodies, RUBBLE_GROUP_BODIES));

    // Last step's contacts chained per particle, for the rows to find their impulses.
    const cl_uint previousCount = warmStart ? contacts_.previousCount : 0u;
    if (previousCount > 0) {
        RUBBLE_TRY(contacts_.next.reserve(c.context(), previousCount * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, contacts_.head, RUBBLE_EMPTY_CELL, particles_.count * sizeof(cl_uint),
                        &profile_));
        RUBBLE_TRY(Dispatch(c, KernelId::LinkPrevious, &profile_)
                       .arg(previousCount)
                       .arg(contacts_.previous)
                       .arg(contacts_.head)
                       .arg(contacts_.next)
                       .run(previousCount, RUBBLE_GROUP_CONTACTS));
    }
    const cl_uint warm = previousCount > 0 ? 1u : 0u;
    return Dispatch(c, KernelId::BuildJacobiRows, &profile_)
        .arg(status_)
        .arg(contacts_.contacts)
        .arg(bodies_.poses)
        .arg(bodies_.atStart)
        .arg(bodies_.jacobi)
        .arg(contacts_.surfaces)
        .arg(contacts_.bodyCount)
        .arg(params)
        .arg(warm)
        .arg(contacts_.head)
        .arg(contacts_.next)
        .arg(contacts_.previous)
        .arg(contacts_.previousRows)
        .arg(contacts_.rows)
        .run(strideItems(), RUBBLE_GROUP_CONTACTS);
}

Status Pipeline::solveJacobi(int iterations, float relaxation, bool warmStart) {
    const Context& c = *context_;
    const cl_uint bodies = bodies_.count;
    RUBBLE_TRY(copyVelocities(bodies_.before));
    // Warm-started impulses (or the dense solver's) act before the first sweep; this gather
    // reads the rows whole and keeps each entry's arm for the later ones.
    RUBBLE_TRY(Dispatch(c, KernelId::GatherJacobiRows, &profile_)
                   .arg(bodies)
                   .arg(contacts_.rows)
                   .arg(contacts_.bodyStart)
                   .arg(contacts_.bodyList)
                   .arg(bodies_.before)
                   .arg(bodies_.jacobi)
                   .arg(bodies_.flags)
                   .arg(bodies_.velocities)
                   .arg(contacts_.arms)
                   .run(bodies, RUBBLE_GROUP_BODIES));
    for (int k = 0; k < iterations; ++k) {
        const cl_uint last = k + 1 == iterations ? 1u : 0u;
        RUBBLE_TRY(Dispatch(c, KernelId::SolveJacobiRows, &profile_)
                       .arg(status_)
                       .arg(contacts_.rows)
                       .arg(bodies_.velocities)
                       .arg(relaxation)
                       .arg(last)
                       .arg(contacts_.impulses)
                       .run(strideItems(), RUBBLE_GROUP_CONTACTS));
        RUBBLE_TRY(Dispatch(c, KernelId::GatherJacobi, &profile_)
                       .arg(bodies)
                       .arg(contacts_.impulses)
                       .arg(contacts_.bodyStart)
                       .arg(contacts_.bodyList)
                       .arg(contacts_.arms)
                       .arg(bodies_.before)
                       .arg(bodies_.jacobi)
                       .arg(bodies_.flags)
                       .arg(bodies_.velocities)
                       .run(bodies, RUBBLE_GROUP_BODIES));
    }
    RUBBLE_TRY(absorbVelocityChange());
    // This step's contacts and impulses become the next step's warm start.
    if (warmStart) {
        std::swap(contacts_.contacts, contacts_.previous);
        std::swap(contacts_.rows, contacts_.previousRows);
        contacts_.previousCount = contacts_.count;
        // The swapped-in buffers must still hold a full step.
        RUBBLE_TRY(setContactCapacity(contacts_.capacity, contacts_.growable));
    }
    return {};
}

Status Pipeline::gatherObstacleImpulses() {
    const cl_uint count = obstacles_.count;
    RUBBLE_TRY(Dispatch(*context_, KernelId::GatherObstacleImpulses, &profile_)
                   .arg(count)
                   .arg(obstacles_.bodies)
                   .arg(contacts_.rows)
                   .arg(contacts_.bodyStart)
                   .arg(contacts_.bodyList)
                   .arg(obstacles_.impulses)
                   .run(count, RUBBLE_GROUP_BODIES));
    // Read without waiting: the host applies them in the next step.
    return enqueueDownload(*context_, obstacles_.impulses, std::span(impulsesHost_), &profile_);
}

} // namespace rubble::gpu
