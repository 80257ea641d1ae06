// host/gpu/sleep.cpp: sleeping on the device: each body by itself (kernels/sleep.cl), or by
// islands (SAT, kernels/islands.cl). Argument order is the kernel signature's.
#include "host/gpu/sleep.h"

#include "host/core/assert.h"

namespace rubble::gpu {
namespace {

// A joint group wakes as one: pass 0 marks the groups with an awake member, then `wakePass`
// (1 after sleepBodies, 2 before the solve) wakes them; pass 2 marks them with the collision
// round `collisionRound` when it is above 0.
Status wakeJointGroups(StageQueue& q, DeviceBodies& b, const DeviceJoints& g, cl_uint wakePass,
                       cl_uint collisionRound = 0) {
    const cl_uint members = g.bodyCount;
    for (const cl_uint pass : {0u, wakePass})
        RUBBLE_TRY(Dispatch(q.c(), KernelId::WakeJointGroups, &q.profile())
                       .arg(members)
                       .arg(g.bodies)
                       .arg(g.groupOf)
                       .arg(b.flags)
                       .arg(b.slowFor)
                       .arg(g.groupVotes)
                       .arg(b.restless)
                       .arg(pass)
                       .arg(collisionRound)
                       .arg(q.status())
                       .run(members, RUBBLE_GROUP_BODIES));
    return {};
}

} // namespace

Status wakeTouched(StageQueue& q, DeviceBodies& b, const ContactBuffers& k) {
    return Dispatch(q.c(), KernelId::WakeTouched, &q.profile())
        .arg(q.status())
        .arg(k.contacts)
        .arg(b.atStart)
        .arg(b.flags)
        .arg(b.slowFor)
        .run(q.strideItems(k.capacity, RUBBLE_GROUP_CONTACTS), RUBBLE_GROUP_CONTACTS);
}

Status wakeTouchedPairs(StageQueue& q, DeviceBodies& b, const PairStore& pairs,
                        const DeviceJoints& joints, std::uint32_t round) {
    const Context& c = q.c();
    const cl_uint collisionRound = round;
    RUBBLE_TRY(Dispatch(c, KernelId::WakeTouchedPairs, &q.profile())
                   .with([&](Dispatch& d) { pairs.bindCurrent(d); })
                   .arg(pairs.manifolds)
                   .arg(b.atStart)
                   .arg(b.flags)
                   .arg(b.slowFor)
                   .arg(b.restless)
                   .arg(collisionRound)
                   .arg(q.status())
                   .run(pairs.strideItems(q), c.workSizes().pairGroup));
    if (joints.groupCount == 0) return {};
    RUBBLE_TRY(fill(c, joints.groupVotes, 0u, joints.groupCount * sizeof(cl_uint), &q.profile()));
    return wakeJointGroups(q, b, joints, 2u, collisionRound);
}

Status wakeStillPairs(StageQueue& q, DeviceBodies& b, const PairStore& pairs, std::uint32_t round) {
    const Context& c = q.c();
    const cl_uint collisionRound = round;
    const std::size_t group = c.workSizes().pairGroup;
    return Dispatch(c, KernelId::WakeStillPairs, &q.profile())
        .with([&](Dispatch& d) { pairs.bindPrevious(d); })
        .arg(pairs.previous.impulseCount)
        .arg(b.flags)
        .arg(b.slowFor)
        .arg(b.restless)
        .arg(collisionRound)
        .arg(q.status())
        .run(q.strideItems(pairs.previous.capacity, group), group);
}

Status sleepBodies(StageQueue& q, DeviceBodies& b, const PairStore* pairs, const ContactBuffers* k,
                   const DeviceJoints& g, float dt) {
    const Context& c = q.c();
    Profile* profile = &q.profile();
    // Restless marks from the contacts: the pairs with points of PGS, or the Jacobi rows.
    if (pairs) {
        RUBBLE_TRY(Dispatch(c, KernelId::MarkRestlessPairs, profile)
                       .with([&](Dispatch& d) { pairs->bindCurrent(d); })
                       .arg(pairs->manifolds)
                       .arg(b.velocities)
                       .arg(b.flags)
                       .arg(b.restless)
                       .run(pairs->strideItems(q), c.workSizes().pairGroup));
        if (g.count > 0) {
            const cl_uint joints = g.count;
            RUBBLE_TRY(Dispatch(c, KernelId::MarkRestlessJoints, profile)
                           .arg(joints)
                           .arg(g.joints)
                           .arg(b.velocities)
                           .arg(b.flags)
                           .arg(b.restless)
                           .run(joints, RUBBLE_GROUP_BODIES));
        }
    } else {
        RUBBLE_ASSERT(k != nullptr);
        RUBBLE_TRY(
            Dispatch(c, KernelId::MarkRestless, profile)
                .arg(q.status())
                .arg(k->rows)
                .arg(b.velocities)
                .arg(b.flags)
                .arg(b.restless)
                .run(q.strideItems(k->capacity, RUBBLE_GROUP_CONTACTS), RUBBLE_GROUP_CONTACTS));
    }
    // Joint groups sleep as one: a member that would stay awake holds the others.
    const cl_uint members = g.bodyCount;
    const bool groups = pairs && g.groupCount > 0;
    if (groups) {
        RUBBLE_TRY(fill(c, g.groupVotes, 0u, g.groupCount * sizeof(cl_uint), profile));
        RUBBLE_TRY(Dispatch(c, KernelId::VoteJointGroups, profile)
                       .arg(members)
                       .arg(g.bodies)
                       .arg(g.groupOf)
                       .arg(b.flags)
                       .arg(b.slowFor)
                       .arg(b.restless)
                       .arg(b.velocities)
                       .arg(dt)
                       .arg(g.groupVotes)
                       .run(members, RUBBLE_GROUP_BODIES));
        RUBBLE_TRY(Dispatch(c, KernelId::HoldJointGroups, profile)
                       .arg(members)
                       .arg(g.bodies)
                       .arg(g.groupOf)
                       .arg(g.groupVotes)
                       .arg(b.restless)
                       .run(members, RUBBLE_GROUP_BODIES));
    }
    const cl_uint count = b.count;
    RUBBLE_TRY(Dispatch(c, KernelId::SleepBodies, profile)
                   .arg(count)
                   .arg(q.status())
                   .arg(b.flags)
                   .arg(b.velocities)
                   .arg(b.momenta)
                   .arg(b.slowFor)
                   .arg(b.restless)
                   .arg(dt)
                   .run(count, RUBBLE_GROUP_BODIES));
    // A group with an awake member wakes as one.
    return groups ? wakeJointGroups(q, b, g, 1u) : Status{};
}

Status DeviceIslands::create(StageQueue& q, const DeviceBodies& b, std::span<const float> radii) {
    const Context& c = q.c();
    const std::size_t n = b.count, word = sizeof(cl_uint);
    RUBBLE_TRY(upload(c, radii_, radii));
    for (Buffer* perBody : {&slowFor_, &group_, &wasAsleep_, &restless_, &marks_, &labels_,
                            &groupFirst_, &roots_, &island_, &islandSlowFor_})
        RUBBLE_TRY(perBody->reserve(c.context(), n * word));
    reset(b);
    return {};
}

void DeviceIslands::reset(const DeviceBodies& b) {
    asleep_ = 0;
    for (std::size_t i = 0; i < b.deviceMasses.size(); ++i)
        if (!b.kinematic[i] && (b.deviceMasses[i].flags & RUBBLE_BODY_ASLEEP)) ++asleep_;
}

Status DeviceIslands::prepare(StageQueue& q, const DeviceBodies& b) {
    // At the first wake or update, as the CPU's state is made at its first call.
    if (prepared_) return {};
    prepared_ = true;
    const cl_uint count = b.count;
    return Dispatch(q.c(), KernelId::PrepareIslands, &q.profile())
        .arg(count)
        .arg(b.flags)
        .arg(slowFor_)
        .arg(group_)
        .arg(wasAsleep_)
        .run(count, RUBBLE_GROUP_BODIES);
}

Status DeviceIslands::wake(StageQueue& q, DeviceBodies& b, const PairStore& pairs,
                           const DeviceJoints& joints, bool kinematicTouches) {
    const Context& c = q.c();
    Profile* profile = &q.profile();
    RUBBLE_TRY(prepare(q, b));
    const cl_uint count = b.count, capacity = pairs.current.capacity;
    RUBBLE_TRY(fill(c, marks_, 0u, std::size_t(count) * sizeof(cl_uint), profile));
    RUBBLE_TRY(Dispatch(c, KernelId::MarkIslandWakeBodies, profile)
                   .arg(count)
                   .arg(capacity)
                   .arg(pairs.current.count)
                   .arg(b.flags)
                   .arg(b.masses)
                   .arg(b.atStart)
                   .arg(radii_)
                   .arg(wasAsleep_)
                   .arg(group_)
                   .arg(restless_)
                   .arg(marks_)
                   .run(count, RUBBLE_GROUP_BODIES));
    const cl_uint kinematic = kinematicTouches ? 1u : 0u;
    RUBBLE_TRY(Dispatch(c, KernelId::MarkIslandWakePairs, profile)
                   .with([&](Dispatch& d) { pairs.bindCurrent(d); })
                   .arg(pairs.summaries)
                   .arg(pairs.manifolds)
                   .arg(kinematic)
                   .arg(b.flags)
                   .arg(b.masses)
                   .arg(restless_)
                   .arg(group_)
                   .arg(marks_)
                   .run(pairs.strideItems(q), c.workSizes().pairGroup));
    if (joints.count > 0) {
        const cl_uint jointCount = joints.count;
        RUBBLE_TRY(Dispatch(c, KernelId::MarkIslandWakeJoints, profile)
                       .arg(jointCount)
                       .arg(joints.joints)
                       .arg(capacity)
                       .arg(pairs.current.count)
                       .arg(b.flags)
                       .arg(b.masses)
                       .arg(restless_)
                       .arg(group_)
                       .arg(marks_)
                       .run(jointCount, RUBBLE_GROUP_BODIES));
    }
    return Dispatch(c, KernelId::WakeIslandBodies, profile)
        .arg(count)
        .arg(capacity)
        .arg(pairs.current.count)
        .arg(b.masses)
        .arg(group_)
        .arg(marks_)
        .arg(b.flags)
        .arg(q.status())
        .run(count, RUBBLE_GROUP_BODIES);
}

Status DeviceIslands::update(StageQueue& q, DeviceBodies& b, const PairStore& pairs,
                             const DeviceJoints& joints, float dt) {
    const Context& c = q.c();
    Profile* profile = &q.profile();
    RUBBLE_TRY(prepare(q, b));
    // The status block was last read after the step's last collision round.
    roundsWoken_ = q.lastStatus().woken;
    const cl_uint count = b.count;
    // Each body's slow time and restless word, its own island; the groups' smallest members.
    RUBBLE_TRY(fill(c, groupFirst_, 0xffffffffu, std::size_t(count) * sizeof(cl_uint), profile));
    RUBBLE_TRY(Dispatch(c, KernelId::MeasureIslandBodies, profile)
                   .arg(count)
                   .arg(b.flags)
                   .arg(b.masses)
                   .arg(b.velocities)
                   .arg(radii_)
                   .arg(wasAsleep_)
                   .arg(group_)
                   .arg(slowFor_)
                   .arg(restless_)
                   .arg(labels_)
                   .arg(groupFirst_)
                   .arg(island_)
                   .arg(islandSlowFor_)
                   .arg(dt)
                   .run(count, RUBBLE_GROUP_BODIES));
    // The islands: the groups linked first (each body writes its own link), then one launch per
    // kind of edge, each joining all of its edges.
    RUBBLE_TRY(Dispatch(c, KernelId::HookIslandGroups, profile)
                   .arg(count)
                   .arg(group_)
                   .arg(groupFirst_)
                   .arg(labels_)
                   .run(count, RUBBLE_GROUP_BODIES));
    RUBBLE_TRY(Dispatch(c, KernelId::UniteIslandPairs, profile)
                   .with([&](Dispatch& d) { pairs.bindCurrent(d); })
                   .arg(pairs.summaries)
                   .arg(b.flags)
                   .arg(b.masses)
                   .arg(b.velocities)
                   .arg(slowFor_)
                   .arg(restless_)
                   .arg(labels_)
                   .run(pairs.strideItems(q), c.workSizes().pairGroup));
    if (joints.count > 0) {
        const cl_uint jointCount = joints.count;
        RUBBLE_TRY(Dispatch(c, KernelId::UniteIslandJoints, profile)
                       .arg(jointCount)
                       .arg(joints.joints)
                       .arg(b.masses)
                       .arg(labels_)
                       .run(jointCount, RUBBLE_GROUP_BODIES));
    }
    RUBBLE_TRY(Dispatch(c, KernelId::GatherIslands, profile)
                   .arg(count)
                   .arg(b.flags)
                   .arg(b.masses)
                   .arg(slowFor_)
                   .arg(restless_)
                   .arg(labels_)
                   .arg(roots_)
                   .arg(island_)
                   .arg(islandSlowFor_)
                   .run(count, RUBBLE_GROUP_BODIES));
    return Dispatch(c, KernelId::SleepIslands, profile)
        .arg(count)
        .arg(q.status())
        .arg(b.masses)
        .arg(roots_)
        .arg(island_)
        .arg(islandSlowFor_)
        .arg(b.flags)
        .arg(b.velocities)
        .arg(b.momenta)
        .arg(slowFor_)
        .arg(group_)
        .arg(wasAsleep_)
        .run(count, RUBBLE_GROUP_BODIES);
}

bool DeviceIslands::met(const DeviceStatus& st) {
    asleep_ = st.asleep;
    return st.fellAsleep > 0 || st.woken > roundsWoken_;
}

} // namespace rubble::gpu
