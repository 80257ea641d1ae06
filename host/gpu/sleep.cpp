// host/gpu/sleep.cpp: dispatch of the device's stage sleepBodies (kernels/sleep.cl): restless
// marks from this step's rows, then each body's sleep. The CPU twin is sleepBodies in
// host/dynamics/sleep.cpp. Argument order is the kernel signature's.
#include <algorithm>

#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::sleepBodies(float dt) {
    // Restless marks from the contacts: the Jacobi rows, or the SAT method's pairs with points.
    if (sat_.enabled) {
        const Context& c = *context_;
        const cl_uint capacity = sat_.current.capacity;
        const std::size_t group = c.workSizes().pairGroup;
        const std::size_t units = std::max<std::uint32_t>(1, c.device().computeUnits);
        const std::size_t items =
            std::min(units * RUBBLE_STRIDE_GROUPS_PER_UNIT * group, roundUp(capacity, group));
        RUBBLE_TRY(Dispatch(c, KernelId::MarkRestlessPairs, &profile_)
                       .arg(capacity)
                       .arg(sat_.current.count)
                       .arg(sat_.current.pairs)
                       .arg(sat_.manifolds)
                       .arg(bodies_.velocities)
                       .arg(bodies_.flags)
                       .arg(bodies_.restless)
                       .run(items, group));
    } else {
        RUBBLE_TRY(Dispatch(*context_, KernelId::MarkRestless, &profile_)
                       .arg(status_)
                       .arg(contacts_.rows)
                       .arg(bodies_.velocities)
                       .arg(bodies_.flags)
                       .arg(bodies_.restless)
                       .run(strideItems(), RUBBLE_GROUP_CONTACTS));
    }
    const cl_uint count = bodies_.count;
    return Dispatch(*context_, KernelId::SleepBodies, &profile_)
        .arg(count)
        .arg(status_)
        .arg(bodies_.flags)
        .arg(bodies_.velocities)
        .arg(bodies_.momenta)
        .arg(bodies_.slowFor)
        .arg(bodies_.restless)
        .arg(dt)
        .run(count, RUBBLE_GROUP_BODIES);
}

} // namespace rubble::gpu
