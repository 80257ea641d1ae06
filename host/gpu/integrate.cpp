// host/gpu/integrate.cpp: dispatch of the integration stages (kernels/integrate.cl); the CPU
// twins are in host/core/integrate.cpp. Argument order is the kernel signature's.
#include "host/gpu/integrate.h"

#include <algorithm>

namespace rubble::gpu {

Status integrateVelocities(StageQueue& q, DeviceBodies& b, shared::float4 gravity, float dt) {
    const cl_uint count = b.count;
    const cl_float4 g = {{gravity.x, gravity.y, gravity.z, gravity.w}};
    return Dispatch(q.c(), KernelId::IntegrateVelocities, &q.profile())
        .arg(count)
        .arg(b.momenta)
        .arg(b.forces)
        .arg(b.masses)
        .arg(b.flags)
        .arg(b.poses)
        .arg(b.velocities)
        .arg(b.atStart)
        .arg(g)
        .arg(dt)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status absorbVelocityChange(StageQueue& q, DeviceBodies& b) {
    const cl_uint count = b.count;
    return Dispatch(q.c(), KernelId::AbsorbVelocityChange, &q.profile())
        .arg(count)
        .arg(b.momenta)
        .arg(b.before)
        .arg(b.velocities)
        .arg(b.masses)
        .arg(b.poses)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status integratePositions(StageQueue& q, DeviceBodies& b, float dt, bool symplectic,
                          bool pushesFollow) {
    const cl_uint count = b.count;
    const cl_uint isSymplectic = symplectic ? 1u : 0u, follow = pushesFollow ? 1u : 0u;
    return Dispatch(q.c(), KernelId::IntegratePositions, &q.profile())
        .arg(count)
        .arg(q.status())
        .arg(b.flags)
        .arg(b.poses)
        .arg(b.velocities)
        .arg(b.atStart)
        .arg(b.momenta)
        .arg(b.masses)
        .arg(dt)
        .arg(isSymplectic)
        .arg(b.jacobi)
        .arg(follow)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status sumBodyEnergy(StageQueue& q, DeviceBodies& b, EnergyBuffers& e, shared::float4 gravity,
                     bool restart) {
    const cl_uint count = b.count, again = restart ? 1u : 0u;
    const cl_float4 g = {{gravity.x, gravity.y, gravity.z, 0.0f}};
    RUBBLE_TRY(e.energies.reserve(q.c().context(), std::max<cl_uint>(count, 1) * sizeof(float)));
    RUBBLE_TRY(e.atLowest.reserve(q.c().context(), std::max<cl_uint>(count, 1) * sizeof(float)));
    RUBBLE_TRY(e.lowest.reserve(q.c().context(), sizeof(float)));
    // One group: it strides through the bodies and writes the total itself.
    return Dispatch(q.c(), KernelId::SumBodyEnergy, &q.profile())
        .arg(count)
        .arg(q.status())
        .arg(b.poses)
        .arg(b.velocities)
        .arg(b.momenta)
        .arg(b.masses)
        .arg(g)
        .arg(again)
        .arg(e.energies)
        .arg(e.atLowest)
        .arg(e.lowest)
        .run(RUBBLE_GROUP_BODIES, RUBBLE_GROUP_BODIES);
}

} // namespace rubble::gpu
