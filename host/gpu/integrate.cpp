// host/gpu/integrate.cpp: dispatch of OpenCL stages 1 and 6 (kernels/integrate.cl); the CPU
// twins are in host/core/integrate.cpp. Argument order is the kernel signature's.
#include "rubble/shared/constants.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::integrateVelocities(shared::float4 gravity, float dt) {
    const cl_uint count = bodies_.count;
    const cl_float4 g = {{gravity.x, gravity.y, gravity.z, gravity.w}};
    return Dispatch(*context_, KernelId::IntegrateVelocities, &profile_)
        .arg(count)
        .arg(bodies_.momenta)
        .arg(bodies_.forces)
        .arg(bodies_.masses)
        .arg(bodies_.flags)
        .arg(bodies_.poses)
        .arg(bodies_.velocities)
        .arg(bodies_.atStart)
        .arg(g)
        .arg(dt)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status Pipeline::absorbVelocityChange() {
    const cl_uint count = bodies_.count;
    return Dispatch(*context_, KernelId::AbsorbVelocityChange, &profile_)
        .arg(count)
        .arg(bodies_.momenta)
        .arg(bodies_.before)
        .arg(bodies_.velocities)
        .arg(bodies_.masses)
        .arg(bodies_.poses)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status Pipeline::integratePositions(float dt, bool symplectic, bool pushesFollow) {
    const cl_uint count = bodies_.count;
    const cl_uint isSymplectic = symplectic ? 1u : 0u, follow = pushesFollow ? 1u : 0u;
    return Dispatch(*context_, KernelId::IntegratePositions, &profile_)
        .arg(count)
        .arg(status_)
        .arg(bodies_.flags)
        .arg(bodies_.poses)
        .arg(bodies_.velocities)
        .arg(bodies_.atStart)
        .arg(bodies_.momenta)
        .arg(bodies_.masses)
        .arg(dt)
        .arg(isSymplectic)
        .arg(bodies_.jacobi)
        .arg(follow)
        .run(count, RUBBLE_GROUP_BODIES);
}

} // namespace rubble::gpu
