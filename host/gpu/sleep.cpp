// host/gpu/sleep.cpp: dispatch of the device's stage sleepBodies (kernels/sleep.cl): restless
// marks from this step's rows, then each body's sleep. The CPU twin is sleepBodies in
// host/dynamics/sleep.cpp. Argument order is the kernel signature's.
#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::sleepBodies(float dt) {
    RUBBLE_TRY(Dispatch(*context_, KernelId::MarkRestless, &profile_)
                   .arg(status_)
                   .arg(contacts_.rows)
                   .arg(bodies_.velocities)
                   .arg(bodies_.flags)
                   .arg(bodies_.restless)
                   .run(strideItems(), RUBBLE_GROUP_CONTACTS));
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
