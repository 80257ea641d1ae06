// host/gpu/sleep.cpp: dispatch of the device's stages wakeTouched (before the rows: sleeping
// bodies touched by a waking one wake) and sleepBodies (kernels/sleep.cl): restless marks from
// this step's rows, then each body's sleep. The CPU twins, of the same names, are in
// host/dynamics/sleep.cpp. Argument order is the kernel signature's.
#include <algorithm>

#include "host/gpu/pipeline.h"

namespace rubble::gpu {

Status Pipeline::wakeTouched() {
    return Dispatch(*context_, KernelId::WakeTouched, &profile_)
        .arg(status_)
        .arg(contacts_.contacts)
        .arg(bodies_.atStart)
        .arg(bodies_.flags)
        .arg(bodies_.slowFor)
        .run(strideItems(), RUBBLE_GROUP_CONTACTS);
}

Status Pipeline::wakeTouchedPairs(std::uint32_t round) {
    const Context& c = *context_;
    const cl_uint collisionRound = round;
    RUBBLE_TRY(Dispatch(c, KernelId::WakeTouchedPairs, &profile_)
                   .with([&](Dispatch& d) { bindPairs(d); })
                   .arg(sat_.manifolds)
                   .arg(bodies_.atStart)
                   .arg(bodies_.flags)
                   .arg(bodies_.slowFor)
                   .arg(bodies_.restless)
                   .arg(collisionRound)
                   .arg(status_)
                   .run(pairStrideItems(), c.workSizes().pairGroup));
    const PgsBuffers& g = pgs_;
    if (g.jointGroupCount == 0) return {};
    // A joint group wakes as one: the members of a group with an awake member.
    RUBBLE_TRY(fill(c, g.groupVotes, 0u, g.jointGroupCount * sizeof(cl_uint), &profile_));
    return wakeJointGroups(2u, collisionRound);
}

Status Pipeline::wakeStillPairs(std::uint32_t round) {
    const Context& c = *context_;
    const cl_uint collisionRound = round;
    return Dispatch(c, KernelId::WakeStillPairs, &profile_)
        .with([&](Dispatch& d) { bindPreviousPairs(d); })
        .arg(sat_.previous.impulseCount)
        .arg(bodies_.flags)
        .arg(bodies_.slowFor)
        .arg(bodies_.restless)
        .arg(collisionRound)
        .arg(status_)
        .run(strideItems(sat_.previous.capacity, c.workSizes().pairGroup), c.workSizes().pairGroup);
}

Status Pipeline::wakeJointGroups(cl_uint wakePass, cl_uint collisionRound) {
    const PgsBuffers& g = pgs_;
    const cl_uint members = g.jointBodyCount;
    for (const cl_uint pass : {0u, wakePass})
        RUBBLE_TRY(Dispatch(*context_, KernelId::WakeJointGroups, &profile_)
                       .arg(members)
                       .arg(g.jointBodies)
                       .arg(g.jointGroupOf)
                       .arg(bodies_.flags)
                       .arg(bodies_.slowFor)
                       .arg(g.groupVotes)
                       .arg(bodies_.restless)
                       .arg(pass)
                       .arg(collisionRound)
                       .arg(status_)
                       .run(members, RUBBLE_GROUP_BODIES));
    return {};
}

Status Pipeline::sleepBodies(float dt) {
    // Restless marks from the contacts: the Jacobi rows, or the pairs with points of PGS.
    if (pairPgs()) {
        const Context& c = *context_;
        RUBBLE_TRY(Dispatch(c, KernelId::MarkRestlessPairs, &profile_)
                       .with([&](Dispatch& d) { bindPairs(d); })
                       .arg(sat_.manifolds)
                       .arg(bodies_.velocities)
                       .arg(bodies_.flags)
                       .arg(bodies_.restless)
                       .run(pairStrideItems(), c.workSizes().pairGroup));
        if (pgs_.jointCount > 0) {
            const cl_uint joints = pgs_.jointCount;
            RUBBLE_TRY(Dispatch(c, KernelId::MarkRestlessJoints, &profile_)
                           .arg(joints)
                           .arg(pgs_.joints)
                           .arg(bodies_.velocities)
                           .arg(bodies_.flags)
                           .arg(bodies_.restless)
                           .run(joints, RUBBLE_GROUP_BODIES));
        }
    } else {
        RUBBLE_TRY(Dispatch(*context_, KernelId::MarkRestless, &profile_)
                       .arg(status_)
                       .arg(contacts_.rows)
                       .arg(bodies_.velocities)
                       .arg(bodies_.flags)
                       .arg(bodies_.restless)
                       .run(strideItems(), RUBBLE_GROUP_CONTACTS));
    }
    // Joint groups sleep as one: a member that would stay awake holds the others.
    const Context& c = *context_;
    const PgsBuffers& g = pgs_;
    const cl_uint members = g.jointBodyCount;
    const bool groups = pairPgs() && g.jointGroupCount > 0;
    if (groups) {
        RUBBLE_TRY(fill(c, g.groupVotes, 0u, g.jointGroupCount * sizeof(cl_uint), &profile_));
        RUBBLE_TRY(Dispatch(c, KernelId::VoteJointGroups, &profile_)
                       .arg(members)
                       .arg(g.jointBodies)
                       .arg(g.jointGroupOf)
                       .arg(bodies_.flags)
                       .arg(bodies_.slowFor)
                       .arg(bodies_.restless)
                       .arg(bodies_.velocities)
                       .arg(dt)
                       .arg(g.groupVotes)
                       .run(members, RUBBLE_GROUP_BODIES));
        RUBBLE_TRY(Dispatch(c, KernelId::HoldJointGroups, &profile_)
                       .arg(members)
                       .arg(g.jointBodies)
                       .arg(g.jointGroupOf)
                       .arg(g.groupVotes)
                       .arg(bodies_.restless)
                       .run(members, RUBBLE_GROUP_BODIES));
    }
    const cl_uint count = bodies_.count;
    RUBBLE_TRY(Dispatch(*context_, KernelId::SleepBodies, &profile_)
                   .arg(count)
                   .arg(status_)
                   .arg(bodies_.flags)
                   .arg(bodies_.velocities)
                   .arg(bodies_.momenta)
                   .arg(bodies_.slowFor)
                   .arg(bodies_.restless)
                   .arg(dt)
                   .run(count, RUBBLE_GROUP_BODIES));
    // A group with an awake member wakes as one.
    return groups ? wakeJointGroups(1u) : Status{};
}

} // namespace rubble::gpu
