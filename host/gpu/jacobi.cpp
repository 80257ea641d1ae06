// host/gpu/jacobi.cpp: dispatch of the Jacobi solve (kernels/jacobi.cl). The CPU twins are in
// host/dynamics/jacobi.cpp. Argument order is the kernel signature's; stages over contacts
// stride through the count the status block holds.
#include "host/gpu/jacobi.h"

#include "host/gpu/integrate.h"

namespace rubble::gpu {
namespace {

std::size_t contactItems(const StageQueue& q, const ContactBuffers& k) {
    return q.strideItems(k.capacity, RUBBLE_GROUP_CONTACTS);
}

} // namespace

Status prepareJacobiBodies(StageQueue& q, DeviceBodies& b) {
    const cl_uint bodies = b.count;
    return Dispatch(q.c(), KernelId::PrepareJacobiBodies, &q.profile())
        .arg(bodies)
        .arg(b.masses)
        .arg(b.flags)
        .arg(b.poses)
        .arg(b.jacobi)
        .run(bodies, RUBBLE_GROUP_BODIES);
}

Status JacobiSolve::buildRows(StageQueue& q, DeviceBodies& b, ContactBuffers& k,
                              std::uint32_t particles, const shared::SolverParams& params,
                              bool warmStart) {
    const Context& c = q.c();
    Profile* profile = &q.profile();
    const cl_uint bodies = b.count;
    const std::size_t items = contactItems(q, k);
    RUBBLE_TRY(prepareJacobiBodies(q, b));
    // Per-body lists: count, scan, fill, then each list in row order.
    RUBBLE_TRY(fill(c, k.bodyCount, 0u, bodies * sizeof(cl_uint), profile));
    RUBBLE_TRY(Dispatch(c, KernelId::CountBodyContacts, profile)
                   .arg(q.status())
                   .arg(k.contacts)
                   .arg(b.flags)
                   .arg(k.bodyCount)
                   .run(items, RUBBLE_GROUP_CONTACTS));
    RUBBLE_TRY(exclusiveScan(q, k.bodyCount, k.bodyStart, bodies));
    RUBBLE_TRY(q.copy(k.bodyStart, k.cursor, (bodies + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(Dispatch(c, KernelId::FillBodyLists, profile)
                   .arg(q.status())
                   .arg(k.contacts)
                   .arg(b.flags)
                   .arg(k.cursor)
                   .arg(k.bodyList)
                   .run(items, RUBBLE_GROUP_CONTACTS));
    RUBBLE_TRY(Dispatch(c, KernelId::SortBodyLists, profile)
                   .arg(bodies)
                   .arg(k.bodyStart)
                   .arg(k.bodyList)
                   .run(bodies, RUBBLE_GROUP_BODIES));

    // Last step's contacts chained per particle, for the rows to find their impulses.
    const cl_uint previousCount = warmStart ? k.previousCount : 0u;
    if (previousCount > 0) {
        RUBBLE_TRY(k.next.reserve(c.context(), previousCount * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, k.head, RUBBLE_EMPTY_CELL, particles * sizeof(cl_uint), profile));
        RUBBLE_TRY(Dispatch(c, KernelId::LinkPrevious, profile)
                       .arg(previousCount)
                       .arg(k.previous)
                       .arg(k.head)
                       .arg(k.next)
                       .run(previousCount, RUBBLE_GROUP_CONTACTS));
    }
    const cl_uint warm = previousCount > 0 ? 1u : 0u;
    return Dispatch(c, KernelId::BuildJacobiRows, profile)
        .arg(q.status())
        .arg(k.contacts)
        .arg(b.poses)
        .arg(b.atStart)
        .arg(b.jacobi)
        .arg(b.surfaces)
        .arg(k.bodyCount)
        .arg(params)
        .arg(warm)
        .arg(k.head)
        .arg(k.next)
        .arg(k.previous)
        .arg(k.previousRows)
        .arg(k.rows)
        .run(items, RUBBLE_GROUP_CONTACTS);
}

Status JacobiSolve::solve(StageQueue& q, DeviceBodies& b, ContactBuffers& k, int iterations,
                          float relaxation) {
    const Context& c = q.c();
    Profile* profile = &q.profile();
    const cl_uint bodies = b.count;
    RUBBLE_TRY(b.copyVelocities(q, b.before));
    // Warm-started impulses (or the dense solver's) act before the first sweep; this gather
    // reads the rows whole and keeps each entry's arm for the later ones.
    RUBBLE_TRY(Dispatch(c, KernelId::GatherJacobiRows, profile)
                   .arg(bodies)
                   .arg(k.rows)
                   .arg(k.bodyStart)
                   .arg(k.bodyList)
                   .arg(b.before)
                   .arg(b.jacobi)
                   .arg(b.flags)
                   .arg(b.velocities)
                   .arg(k.arms)
                   .run(bodies, RUBBLE_GROUP_BODIES));
    for (int it = 0; it < iterations; ++it) {
        const cl_uint last = it + 1 == iterations ? 1u : 0u;
        RUBBLE_TRY(Dispatch(c, KernelId::SolveJacobiRows, profile)
                       .arg(q.status())
                       .arg(k.rows)
                       .arg(b.velocities)
                       .arg(relaxation)
                       .arg(last)
                       .arg(k.impulses)
                       .run(contactItems(q, k), RUBBLE_GROUP_CONTACTS));
        RUBBLE_TRY(Dispatch(c, KernelId::GatherJacobi, profile)
                       .arg(bodies)
                       .arg(k.impulses)
                       .arg(k.bodyStart)
                       .arg(k.bodyList)
                       .arg(k.arms)
                       .arg(b.before)
                       .arg(b.jacobi)
                       .arg(b.flags)
                       .arg(b.velocities)
                       .run(bodies, RUBBLE_GROUP_BODIES));
    }
    return absorbVelocityChange(q, b);
}

Status JacobiSolve::solveDense(StageQueue& q, DeviceBodies& b, ContactBuffers& k,
                               std::uint32_t stride, int iterations, float relaxation) {
    const Context& c = q.c();
    RUBBLE_TRY(buildLcpOnDevice(c, k.rows, k.count, stride, b.velocities, b.masses, b.flags,
                                b.poses, lcp_));
    RUBBLE_TRY(iterateLcpJacobi(c, lcp_, iterations, relaxation, q.status()));
    return storeLcpImpulses(c, lcp_, k.rows);
}

} // namespace rubble::gpu
