// host/gpu/forces.cpp: dispatch of the device's force inputs (kernels/forces.cl). Argument
// order is the kernel signature's.
#include "host/gpu/forces.h"

#include <algorithm>

#include "host/core/assert.h"

namespace rubble::gpu {
namespace {

// Kernel placeObstacles: `count` bodies take the poses, velocities and flags of `states`
// (ObstacleState, each naming its body).
Status placeBodies(StageQueue& q, DeviceBodies& b, const Buffer& states, cl_uint count) {
    return Dispatch(q.c(), KernelId::PlaceObstacles, &q.profile())
        .arg(count)
        .arg(states)
        .arg(b.poses)
        .arg(b.velocities)
        .arg(b.flags)
        .run(count, RUBBLE_GROUP_BODIES);
}

} // namespace

Status applyExplosion(StageQueue& q, DeviceBodies& b, const EventDesc& e) {
    const cl_uint count = b.count;
    const cl_float4 explosion = {{e.centre.x, e.centre.y, e.centre.z, e.radius}};
    const cl_float impulse = e.impulse;
    return Dispatch(q.c(), KernelId::ApplyExplosion, &q.profile())
        .arg(count)
        .arg(explosion)
        .arg(impulse)
        .arg(b.poses)
        .arg(b.flags)
        .arg(b.momenta)
        .arg(b.slowFor)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status ObstacleCoupling::create(StageQueue& q, const DeviceBodies& b) {
    const Context& c = q.c();
    std::vector<cl_uint> obstacles;
    for (std::uint32_t i = 0; i < b.count; ++i)
        if (b.kinematic[i]) obstacles.push_back(i);
    count_ = std::uint32_t(obstacles.size());
    RUBBLE_TRY(upload(c, bodies_, obstacles));
    RUBBLE_TRY(states_.reserve(c.context(), obstacles.size() * sizeof(shared::ObstacleState)));
    RUBBLE_TRY(impulses_.reserve(c.context(), obstacles.size() * sizeof(shared::BodyImpulse)));
    statesHost_.resize(obstacles.size());
    impulsesHost_.assign(obstacles.size(), shared::BodyImpulse{});
    return {};
}

Status ObstacleCoupling::place(StageQueue& q, DeviceBodies& b,
                               std::span<const shared::ObstacleState> states) {
    RUBBLE_ASSERT(states.size() == count_);
    if (states.empty()) return {};
    // Non-blocking: the copy stays put until the step is met.
    std::copy(states.begin(), states.end(), statesHost_.begin());
    RUBBLE_TRY(enqueueUpload(q.c(), states_, std::span<const shared::ObstacleState>(statesHost_),
                             &q.profile()));
    return placeBodies(q, b, states_, count_);
}

Status KinematicTargets::setVelocities(StageQueue& q, DeviceBodies& b,
                                       std::span<const shared::ObstacleState> states) {
    if (states.empty()) return {};
    for (const shared::ObstacleState& s : states)
        b.setKinematicMotion(s.body, (s.flags & RUBBLE_BODY_WAKING) != 0u);
    // Non-blocking: the copy stays put until the step is met.
    velocitiesHost_.assign(states.begin(), states.end());
    RUBBLE_TRY(velocities_.reserve(q.c().context(),
                                   states.size() * sizeof(shared::ObstacleState)));
    RUBBLE_TRY(enqueueUpload(q.c(), velocities_,
                             std::span<const shared::ObstacleState>(velocitiesHost_),
                             &q.profile()));
    const cl_uint count = cl_uint(states.size());
    return Dispatch(q.c(), KernelId::SetKinematicVelocities, &q.profile())
        .arg(count)
        .arg(velocities_)
        .arg(b.velocities)
        .arg(b.flags)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status KinematicTargets::place(StageQueue& q, DeviceBodies& b,
                               std::span<const shared::ObstacleState> targets) {
    if (targets.empty()) return {};
    // Non-blocking: the copy stays put until the step is met.
    statesHost_.assign(targets.begin(), targets.end());
    RUBBLE_TRY(states_.reserve(q.c().context(), targets.size() * sizeof(shared::ObstacleState)));
    RUBBLE_TRY(enqueueUpload(q.c(), states_, std::span<const shared::ObstacleState>(statesHost_),
                             &q.profile()));
    return placeBodies(q, b, states_, cl_uint(targets.size()));
}

Status ObstacleCoupling::gather(StageQueue& q, const Buffer& rows, const Buffer& bodyStart,
                                const Buffer& bodyList) {
    const cl_uint count = count_;
    RUBBLE_TRY(Dispatch(q.c(), KernelId::GatherObstacleImpulses, &q.profile())
                   .arg(count)
                   .arg(bodies_)
                   .arg(rows)
                   .arg(bodyStart)
                   .arg(bodyList)
                   .arg(impulses_)
                   .run(count, RUBBLE_GROUP_BODIES));
    // Read without waiting: the host applies them in the next step.
    return enqueueDownload(q.c(), impulses_, std::span(impulsesHost_), &q.profile());
}

} // namespace rubble::gpu
