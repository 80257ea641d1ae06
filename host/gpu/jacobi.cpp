// host/gpu/jacobi.cpp: dispatch of OpenCL stage 5, solveJacobi (kernels/jacobi.cl): per-body
// row lists, warm start from last step's contacts, rows, and the iterations. The CPU twins are
// in host/dynamics/jacobi.cpp. Argument order is the kernel signature's.
#include <utility>

#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::buildJacobiRows(const shared::SolverParams& params, bool warmStart) {
    const Context& c = *context_;
    const cl_uint count = contacts_.count, bodies = bodies_.count;
    // Per-body lists: count, scan, fill, then each list in row order.
    RUBBLE_TRY(fill(c, contacts_.bodyCount, 0u, bodies * sizeof(cl_uint)));
    RUBBLE_TRY(Dispatch(c, KernelId::CountBodyContacts)
                   .arg(count)
                   .arg(contacts_.contacts)
                   .arg(bodies_.masses)
                   .arg(contacts_.bodyCount)
                   .run(count, RUBBLE_GROUP_CONTACTS));
    RUBBLE_TRY(exclusiveScan(contacts_.bodyCount, contacts_.bodyStart, bodies));
    RUBBLE_CL_CHECK(clEnqueueCopyBuffer(c.queue(), contacts_.bodyStart.mem(),
                                        contacts_.cursor.mem(), 0, 0,
                                        (bodies + 1) * sizeof(cl_uint), 0, nullptr, nullptr));
    RUBBLE_TRY(Dispatch(c, KernelId::FillBodyLists)
                   .arg(count)
                   .arg(contacts_.contacts)
                   .arg(bodies_.masses)
                   .arg(contacts_.cursor)
                   .arg(contacts_.bodyList)
                   .run(count, RUBBLE_GROUP_CONTACTS));
    RUBBLE_TRY(Dispatch(c, KernelId::SortBodyLists)
                   .arg(bodies)
                   .arg(contacts_.bodyStart)
                   .arg(contacts_.bodyList)
                   .run(bodies, RUBBLE_GROUP_BODIES));

    // Last step's contacts chained per particle, for the rows to find their impulses.
    const cl_uint previousCount = warmStart ? contacts_.previousCount : 0u;
    if (previousCount > 0) {
        RUBBLE_TRY(contacts_.next.reserve(c.context(), previousCount * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, contacts_.head, RUBBLE_EMPTY_CELL, particles_.count * sizeof(cl_uint)));
        RUBBLE_TRY(Dispatch(c, KernelId::LinkPrevious)
                       .arg(previousCount)
                       .arg(contacts_.previous)
                       .arg(contacts_.head)
                       .arg(contacts_.next)
                       .run(previousCount, RUBBLE_GROUP_CONTACTS));
    }
    for (Buffer* b : {&contacts_.next, &contacts_.previous, &contacts_.previousRows})
        RUBBLE_TRY(b->reserve(c.context(), 16)); // bound even when empty
    const cl_uint warm = previousCount > 0 ? 1u : 0u;
    return Dispatch(c, KernelId::BuildJacobiRows)
        .arg(count)
        .arg(contacts_.contacts)
        .arg(bodies_.poses)
        .arg(bodies_.velocities)
        .arg(bodies_.masses)
        .arg(contacts_.surfaces)
        .arg(contacts_.bodyCount)
        .arg(params)
        .arg(warm)
        .arg(contacts_.head)
        .arg(contacts_.next)
        .arg(contacts_.previous)
        .arg(contacts_.previousRows)
        .arg(contacts_.rows)
        .run(count, RUBBLE_GROUP_CONTACTS);
}

Status Pipeline::solveJacobi(int iterations, float relaxation, bool warmStart) {
    const Context& c = *context_;
    const cl_uint count = contacts_.count, bodies = bodies_.count;
    RUBBLE_TRY(copyVelocities(bodies_.before));
    auto gather = [&] {
        return Dispatch(c, KernelId::GatherJacobi)
            .arg(bodies)
            .arg(contacts_.rows)
            .arg(contacts_.bodyStart)
            .arg(contacts_.bodyList)
            .arg(bodies_.before)
            .arg(bodies_.masses)
            .arg(bodies_.poses)
            .arg(bodies_.velocities)
            .run(bodies, RUBBLE_GROUP_BODIES);
    };
    if (count > 0) {
        // Warm-started impulses act before the first sweep.
        RUBBLE_TRY(gather());
        for (int k = 0; k < iterations; ++k) {
            const cl_uint last = k + 1 == iterations ? 1u : 0u;
            RUBBLE_TRY(Dispatch(c, KernelId::SolveJacobiRows)
                           .arg(count)
                           .arg(contacts_.rows)
                           .arg(bodies_.velocities)
                           .arg(relaxation)
                           .arg(last)
                           .arg(status_)
                           .run(count, RUBBLE_GROUP_CONTACTS));
            RUBBLE_TRY(gather());
        }
    }
    RUBBLE_TRY(absorbVelocityChange());
    // This step's contacts and impulses become the next step's warm start.
    if (warmStart) {
        std::swap(contacts_.contacts, contacts_.previous);
        std::swap(contacts_.rows, contacts_.previousRows);
        contacts_.previousCount = count;
        // The swapped-in buffers must still hold a full step.
        RUBBLE_TRY(setContactCapacity(contacts_.capacity, contacts_.growable));
    }
    return {};
}

} // namespace rubble::gpu
