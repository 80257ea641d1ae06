// host/gpu/sleep.cpp: sleeping on the device. With SAT, as the host decides (wakeIslandsOnHost,
// updateIslandsOnHost: a HostSleep, the world's islands, over the device's pairs);
// otherwise (particles, or --body-sleep) the dispatch of the device's stages wakeTouched (before
// the rows: sleeping bodies touched by a waking one wake) and sleepBodies (kernels/sleep.cl):
// restless marks from this step's rows, then each body's sleep. The CPU twins of those, of the
// same names, are in host/dynamics/sleep.cpp. Argument order is the kernel signature's.
#include <algorithm>

#include "host/core/assert.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {
namespace {

// The device's flags with the host's asleep bit (a kinematic body keeps the device's flags).
void flagsFromIslands(const HostIslands& h, std::span<const std::uint8_t> kinematic,
                      std::vector<cl_uint>& flags) {
    for (std::size_t i = 0; i < flags.size(); ++i) {
        if (kinematic[i]) continue;
        flags[i] = (flags[i] & ~RUBBLE_BODY_ASLEEP) | (h.masses[i].flags & RUBBLE_BODY_ASLEEP);
    }
}

// The host's asleep bit from the device's flags: an explosion on the device wakes bodies.
void islandsFromFlags(std::span<const cl_uint> flags, std::span<const std::uint8_t> kinematic,
                      HostIslands& h) {
    for (std::size_t i = 0; i < flags.size(); ++i) {
        if (kinematic[i]) continue;
        shared::BodyMass& m = h.masses[i];
        m.flags = (m.flags & ~RUBBLE_BODY_ASLEEP) | (flags[i] & RUBBLE_BODY_ASLEEP);
    }
}

} // namespace

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

void Pipeline::collectTouching() {
    const PgsBuffers& g = pgs_;
    HostIslands& h = islands_;
    h.touching.clear();
    for (std::size_t p = 0; p < g.pairRowsHost.size(); ++p)
        if (g.pairRowsHost[p] & RUBBLE_PGS_POINTS)
            h.touching.push_back({g.pairsHost[p].a, g.pairsHost[p].b});
}

Result<std::uint32_t> Pipeline::wakeIslandsOnHost() {
    HostIslands& h = islands_;
    RUBBLE_ASSERT(h.enabled());
    // Nothing asleep at the end of the last step (or since the host's upload): nothing wakes.
    if (h.asleep == 0) return 0u;
    const Context& c = *context_;
    const std::uint32_t n = bodies_.count;
    // The flags and the velocities before the forces once a step: later rounds change only
    // the flags, and those the host wrote.
    if (!h.stepRead) {
        h.flags.resize(n);
        h.approach.resize(n);
        RUBBLE_TRY(enqueueDownload(c, bodies_.flags, std::span(h.flags), &profile_));
        RUBBLE_TRY(enqueueDownload(c, bodies_.atStart, std::span(h.approach), &profile_));
    }
    RUBBLE_TRY(readPairSummaries());
    if (!h.stepRead) {
        RUBBLE_TRY(finish());
        islandsFromFlags(h.flags, kinematic_, h);
        h.stepRead = true;
    }
    collectTouching();
    const std::uint32_t woken = h.sleep->wake(h.touching, h.masses, h.approach);
    if (woken == 0) return 0u;
    flagsFromIslands(h, kinematic_, h.flags);
    RUBBLE_TRY(upload(c, bodies_.flags, h.flags));
    hostBodies_ = true;
    return woken;
}

Result<std::uint32_t> Pipeline::updateIslandsOnHost(float dt,
                                                    const std::optional<Bodies>& readBack) {
    HostIslands& h = islands_;
    RUBBLE_ASSERT(h.enabled());
    const Context& c = *context_;
    const std::uint32_t n = bodies_.count;
    // The step's velocities, momenta and flags: its read-back's, or read now.
    std::span<shared::BodyVelocity> velocities;
    std::span<shared::BodyMomentum> momenta;
    if (readBack) {
        velocities = readBack->velocities;
        momenta = readBack->momenta;
        h.flags.assign(flagsHost_.begin(), flagsHost_.end());
    } else {
        h.velocities.resize(n);
        h.momenta.resize(n);
        h.flags.resize(n);
        velocities = h.velocities;
        momenta = h.momenta;
        RUBBLE_TRY(enqueueDownload(c, bodies_.velocities, velocities, &profile_));
        RUBBLE_TRY(enqueueDownload(c, bodies_.momenta, momenta, &profile_));
        RUBBLE_TRY(download(c, bodies_.flags, std::span(h.flags), &profile_));
    }
    islandsFromFlags(h.flags, kinematic_, h);
    // The pairs with rows of the step's last collision round, as colorPgs read them.
    collectTouching();
    const HostSleepCounts r = h.sleep->update(h.touching, h.masses, velocities, momenta, dt);
    h.asleep = r.asleep;
    if (r.fellAsleep == 0 && r.woken == 0) return r.asleep;
    // The new flags, and the stopped bodies' zero velocities and momenta (update wrote them on
    // the host); the read-back's flags follow flagsHost_ (takeSleepFlags).
    flagsFromIslands(h, kinematic_, h.flags);
    RUBBLE_TRY(upload(c, bodies_.flags, h.flags));
    if (readBack) flagsHost_.assign(h.flags.begin(), h.flags.end());
    if (r.fellAsleep > 0) {
        RUBBLE_TRY(
            upload(c, bodies_.velocities, std::span<const shared::BodyVelocity>(velocities)));
        RUBBLE_TRY(upload(c, bodies_.momenta, std::span<const shared::BodyMomentum>(momenta)));
    }
    hostBodies_ = true;
    return r.asleep;
}

} // namespace rubble::gpu
