// host/gpu/forces.cpp: dispatch of the device's stage 1 inputs (kernels/forces.cl): explosions
// and the host's bodies placed as obstacles. The CPU path of explosions is
// host/dynamics/forces.cpp. Argument order is the kernel signature's.
#include <algorithm>

#include "host/core/assert.h"
#include "host/core/math.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::applyExplosion(const EventDesc& e) {
    const cl_uint count = bodies_.count;
    const cl_float4 explosion = {{e.centre.x, e.centre.y, e.centre.z, e.radius}};
    const cl_float impulse = e.impulse;
    return Dispatch(*context_, KernelId::ApplyExplosion, &profile_)
        .arg(count)
        .arg(explosion)
        .arg(impulse)
        .arg(bodies_.poses)
        .arg(bodies_.flags)
        .arg(bodies_.momenta)
        .arg(bodies_.slowFor)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status Pipeline::placeObstacles(std::span<const shared::ObstacleState> obstacles) {
    RUBBLE_ASSERT(obstacles.size() == obstacles_.count);
    if (obstacles.empty()) return {};
    // Non-blocking: the copy stays put until the step is met.
    std::copy(obstacles.begin(), obstacles.end(), obstaclesHost_.begin());
    RUBBLE_TRY(enqueueUpload(
        *context_, obstacles_.states,
        std::span<const shared::ObstacleState>(obstaclesHost_).first(obstacles.size()), &profile_));
    const cl_uint count = obstacles_.count;
    return Dispatch(*context_, KernelId::PlaceObstacles, &profile_)
        .arg(count)
        .arg(obstacles_.states)
        .arg(bodies_.poses)
        .arg(bodies_.velocities)
        .arg(bodies_.flags)
        .run(count, RUBBLE_GROUP_BODIES);
}

} // namespace rubble::gpu
