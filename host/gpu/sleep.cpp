// host/gpu/sleep.cpp: sleeping on the device (kernels/sleep.cl) and the host's islands over the
// device's pairs. Argument order is the kernel signature's.
#include "host/gpu/sleep.h"

#include <algorithm>

#include "host/core/assert.h"

namespace rubble::gpu {
namespace {

// The device's flags with the host's asleep bit (a kinematic body keeps the device's flags).
void flagsFromIslands(std::span<const shared::BodyMass> masses,
                      std::span<const std::uint8_t> kinematic, std::vector<cl_uint>& flags) {
    for (std::size_t i = 0; i < flags.size(); ++i) {
        if (kinematic[i]) continue;
        flags[i] = (flags[i] & ~RUBBLE_BODY_ASLEEP) | (masses[i].flags & RUBBLE_BODY_ASLEEP);
    }
}

// The host's asleep bit from the device's flags: an explosion on the device wakes bodies.
void islandsFromFlags(std::span<const cl_uint> flags, std::span<const std::uint8_t> kinematic,
                      std::span<shared::BodyMass> masses) {
    for (std::size_t i = 0; i < flags.size(); ++i) {
        if (kinematic[i]) continue;
        shared::BodyMass& m = masses[i];
        m.flags = (m.flags & ~RUBBLE_BODY_ASLEEP) | (flags[i] & RUBBLE_BODY_ASLEEP);
    }
}

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

void HostIslands::reset(const DeviceBodies& b) {
    masses_ = b.deviceMasses;
    asleep_ = 0;
    for (std::size_t i = 0; i < masses_.size(); ++i)
        if (!b.kinematic[i] && (masses_[i].flags & RUBBLE_BODY_ASLEEP)) ++asleep_;
}

Result<std::uint32_t> HostIslands::wake(StageQueue& q, DeviceBodies& b,
                                        std::span<const BodyPair> touching) {
    // Nothing asleep at the end of the last step (or since the host's upload): nothing wakes.
    if (asleep_ == 0) return 0u;
    const Context& c = q.c();
    // The flags and the velocities before the forces once a step: later rounds change only
    // the flags, and those the host wrote.
    if (!stepRead_) {
        flags_.resize(b.count);
        approach_.resize(b.count);
        RUBBLE_TRY(enqueueDownload(c, b.flags, std::span(flags_), &q.profile()));
        RUBBLE_TRY(enqueueDownload(c, b.atStart, std::span(approach_), &q.profile()));
        RUBBLE_TRY(q.finish());
        islandsFromFlags(flags_, b.kinematic, masses_);
        stepRead_ = true;
    }
    const std::uint32_t woken = sleep_->wake(touching, masses_, approach_);
    if (woken == 0) return 0u;
    flagsFromIslands(masses_, b.kinematic, flags_);
    RUBBLE_TRY(upload(c, b.flags, flags_));
    return woken;
}

Status HostIslands::addKinematicTouches(StageQueue& q, const DeviceBodies& b,
                                        const PairStore& pairs, std::vector<BodyPair>& touching) {
    const Context& c = q.c();
    const std::uint32_t capacity = pairs.current.capacity;
    RUBBLE_TRY(touches_.reserve(c.context(), std::size_t(capacity) * sizeof(shared::BodyPairRecord)));
    RUBBLE_TRY(touchCount_.reserve(c.context(), sizeof(cl_uint)));
    RUBBLE_TRY(fill(c, touchCount_, 0u, sizeof(cl_uint), &q.profile()));
    RUBBLE_TRY(Dispatch(c, KernelId::ListKinematicTouches, &q.profile())
                   .with([&](Dispatch& d) { pairs.bindCurrent(d); })
                   .arg(pairs.manifolds)
                   .arg(b.flags)
                   .arg(touchCount_)
                   .arg(touches_)
                   .run(pairs.strideItems(q), c.workSizes().pairGroup));
    cl_uint count = 0;
    RUBBLE_TRY(download(c, touchCount_, std::span(&count, 1), &q.profile()));
    if (count == 0) return {};
    touchesHost_.resize(std::min<std::uint32_t>(count, capacity));
    RUBBLE_TRY(download(c, touches_, std::span(touchesHost_), &q.profile()));
    for (const shared::BodyPairRecord& t : touchesHost_) touching.push_back({t.a, t.b});
    return {};
}

Result<HostSleepCounts> HostIslands::update(StageQueue& q, DeviceBodies& b,
                                            std::span<const BodyPair> touching, float dt,
                                            const std::optional<Bodies>& readBack) {
    const Context& c = q.c();
    // The step's velocities, momenta and flags: its read-back's, or read now.
    std::span<shared::BodyVelocity> velocities;
    std::span<shared::BodyMomentum> momenta;
    if (readBack) {
        velocities = readBack->velocities;
        momenta = readBack->momenta;
        flags_.assign(b.flagsHost.begin(), b.flagsHost.end());
    } else {
        velocities_.resize(b.count);
        momenta_.resize(b.count);
        flags_.resize(b.count);
        velocities = velocities_;
        momenta = momenta_;
        RUBBLE_TRY(enqueueDownload(c, b.velocities, velocities, &q.profile()));
        RUBBLE_TRY(enqueueDownload(c, b.momenta, momenta, &q.profile()));
        RUBBLE_TRY(download(c, b.flags, std::span(flags_), &q.profile()));
    }
    islandsFromFlags(flags_, b.kinematic, masses_);
    const HostSleepCounts r = sleep_->update(touching, masses_, velocities, momenta, dt);
    asleep_ = r.asleep;
    if (r.fellAsleep == 0 && r.woken == 0) return r;
    // The new flags, and the stopped bodies' zero velocities and momenta (update wrote them on
    // the host); the read-back's flags follow b.flagsHost (takeSleepFlags).
    flagsFromIslands(masses_, b.kinematic, flags_);
    RUBBLE_TRY(upload(c, b.flags, flags_));
    if (readBack) b.flagsHost.assign(flags_.begin(), flags_.end());
    if (r.fellAsleep > 0) {
        RUBBLE_TRY(upload(c, b.velocities, std::span<const shared::BodyVelocity>(velocities)));
        RUBBLE_TRY(upload(c, b.momenta, std::span<const shared::BodyMomentum>(momenta)));
    }
    return r;
}

} // namespace rubble::gpu
