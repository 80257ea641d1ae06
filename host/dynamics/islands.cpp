// host/dynamics/islands.cpp: islands by union-find, and sleeping (last stage of the CPU step).
#include "host/dynamics/islands.h"

#include <algorithm>
#include <limits>

#include "host/core/assert.h"
#include "host/core/math.h"
#include "host/core/union_find.h"

namespace rubble {
namespace {

bool isDynamic(const shared::BodyMass& m) {
    return m.inverseMass > 0.0f;
}

// Sized to the bodies at the first call (or after bodies were added or removed); a body asleep
// then (a restored state) sleeps in no group but alone.
void prepareState(std::span<const shared::BodyMass> masses, SleepState& st) {
    const std::size_t n = masses.size();
    if (st.slowFor.size() == n) return;
    st.slowFor.assign(n, 0.0f);
    st.group.assign(n, kNoGroup);
    st.wasAsleep.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        st.wasAsleep[i] = (masses[i].flags & RUBBLE_BODY_ASLEEP) ? 1 : 0;
}

// The speed of the body's fastest point: the centre's speed plus the turn at the rim, m/s.
float fastestPoint(const shared::BodyVelocity& v, float radius) {
    return glm::length(toVec3(v.linear)) + radius * glm::length(toVec3(v.angular));
}

bool isAsleep(const shared::BodyMass& m) {
    return (m.flags & RUBBLE_BODY_ASLEEP) != 0;
}

// A kinematic body that moves at all: it never sleeps, and wakes and keeps awake what it touches.
bool movingKinematic(const shared::BodyMass& m, const shared::BodyVelocity& v) {
    return (m.flags & RUBBLE_BODY_KINEMATIC) && fastestPoint(v, 1.0f) > 0.0f;
}

// The body pairs of the manifolds with points, into st.touching.
std::span<const BodyPair> touchingPairs(std::span<const Manifold> manifolds, SleepState& st) {
    st.touching.clear();
    for (const Manifold& m : manifolds)
        if (m.count > 0) st.touching.push_back({m.a, m.b});
    return st.touching;
}

} // namespace

std::uint32_t wakeIslands(std::span<const Manifold> manifolds, std::span<const BodyPair> joined,
                          std::span<const float> radii, std::span<shared::BodyMass> masses,
                          std::span<const shared::BodyVelocity> approach, SleepState& st) {
    return wakeIslands(touchingPairs(manifolds, st), joined, radii, masses, approach, st);
}

SleepReport updateSleep(std::span<const Manifold> manifolds, std::span<const BodyPair> joined,
                        std::span<const float> radii, std::span<shared::BodyMass> masses,
                        std::span<shared::BodyVelocity> velocities,
                        std::span<shared::BodyMomentum> momenta, float dt, SleepState& st) {
    return updateSleep(touchingPairs(manifolds, st), joined, radii, masses, velocities, momenta, dt,
                       st);
}

std::uint32_t wakeIslands(std::span<const BodyPair> touching, std::span<const BodyPair> joined,
                          std::span<const float> radii, std::span<shared::BodyMass> masses,
                          std::span<const shared::BodyVelocity> approach, SleepState& st) {
    const std::uint32_t n = std::uint32_t(masses.size());
    RUBBLE_ASSERT(approach.size() == n && radii.size() == n);
    prepareState(masses, st);
    // Nothing asleep, nothing to wake.
    if (std::none_of(masses.begin(), masses.end(),
                     [](const shared::BodyMass& m) { return isAsleep(m); }))
        return 0;
    // Restless: awake and moving, or woken from outside since the last step.
    st.restless.assign(n, 0);
    bool any = false;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (movingKinematic(masses[i], approach[i])) {
            st.restless[i] = 1;
            any = true;
            continue;
        }
        if (!isDynamic(masses[i]) || isAsleep(masses[i])) continue;
        st.restless[i] = st.wasAsleep[i] != 0 || fastestPoint(approach[i], radii[i]) >= kSleepSpeed;
        any = any || st.restless[i];
    }
    if (!any) return 0;
    // What wakes: the sleeping bodies a restless one touches, and the groups of both those and
    // the bodies woken from outside. A body asleep in no group wakes alone.
    st.wakeGroup.assign(n, 0);
    st.wakeBody.assign(n, 0);
    auto mark = [&](std::uint32_t i) {
        if (st.group[i] == kNoGroup)
            st.wakeBody[i] = 1;
        else
            st.wakeGroup[st.group[i]] = 1;
    };
    // Dynamic bodies and moving kinematic ones (restless, never asleep) wake what they touch.
    auto takesPart = [&](std::uint32_t i) { return isDynamic(masses[i]) || st.restless[i]; };
    auto touch = [&](std::uint32_t a, std::uint32_t b) {
        if (!takesPart(a) || !takesPart(b)) return;
        if (st.restless[a] && isAsleep(masses[b])) mark(b);
        if (st.restless[b] && isAsleep(masses[a])) mark(a);
    };
    for (const BodyPair& t : touching) touch(t.a, t.b);
    for (const BodyPair& j : joined) touch(j.a, j.b);
    for (std::uint32_t i = 0; i < n; ++i)
        if (st.restless[i] && st.wasAsleep[i] && st.group[i] != kNoGroup) mark(i);
    // Woken: still of its group and woken from outside for updateSleep (restless, its slow time
    // starting again), with the zero velocities it slept with.
    std::uint32_t woken = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!isDynamic(masses[i]) || !isAsleep(masses[i])) continue;
        if (!st.wakeBody[i] && (st.group[i] == kNoGroup || !st.wakeGroup[st.group[i]])) continue;
        masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
        ++woken;
    }
    return woken;
}

SleepReport updateSleep(std::span<const BodyPair> touching, std::span<const BodyPair> joined,
                        std::span<const float> radii, std::span<shared::BodyMass> masses,
                        std::span<shared::BodyVelocity> velocities,
                        std::span<shared::BodyMomentum> momenta, float dt, SleepState& st) {
    const std::uint32_t n = std::uint32_t(masses.size());
    RUBBLE_ASSERT(velocities.size() == n && momenta.size() == n && radii.size() == n);
    prepareState(masses, st);

    // How long each awake body has been slow; one woken from outside starts again. A body that
    // is not slow, or was just woken from outside, is restless: it wakes what it touches.
    st.restless.assign(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!isDynamic(masses[i]) || (masses[i].flags & RUBBLE_BODY_ASLEEP)) continue;
        const bool wokenFromOutside = st.wasAsleep[i] != 0;
        if (wokenFromOutside) st.slowFor[i] = 0.0f;
        const bool slow = fastestPoint(velocities[i], radii[i]) < kSleepSpeed;
        st.slowFor[i] = slow ? st.slowFor[i] + dt : 0.0f;
        st.restless[i] = !slow || wokenFromOutside ? 1 : 0;
    }
    // A body that a moving kinematic body touches is carried or pushed: restless, never slow.
    for (const BodyPair& t : touching)
        for (const auto& [k, d] : {std::pair{t.a, t.b}, std::pair{t.b, t.a}})
            if (isDynamic(masses[d]) && !isAsleep(masses[d]) &&
                movingKinematic(masses[k], velocities[k])) {
                st.restless[d] = 1;
                st.slowFor[d] = 0.0f;
            }

    // Islands over dynamic bodies: contacts, joints, and the groups that sleep together.
    st.islands.reset(n);
    for (const BodyPair& t : touching)
        if (isDynamic(masses[t.a]) && isDynamic(masses[t.b])) st.islands.unite(t.a, t.b);
    for (const BodyPair& j : joined)
        if (isDynamic(masses[j.a]) && isDynamic(masses[j.b])) st.islands.unite(j.a, j.b);
    st.groupFirst.assign(n, kNoGroup);
    for (std::uint32_t i = 0; i < n; ++i) {
        // Asleep, or asleep until woken from outside this step: still one of its group.
        if (st.group[i] == kNoGroup) continue;
        std::uint32_t& first = st.groupFirst[st.group[i]];
        if (first == kNoGroup)
            first = i;
        else
            st.islands.unite(first, i);
    }

    // Per island: awake, restless and asleep bodies, and the shortest slow time of the awake.
    st.awake.assign(n, 0);
    st.asleep.assign(n, 0);
    st.islandRestless.assign(n, 0);
    st.islandSlowFor.assign(n, std::numeric_limits<float>::infinity());
    SleepReport report;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!isDynamic(masses[i])) continue;
        const std::uint32_t r = st.islands.find(i);
        if (st.awake[r] == 0 && st.asleep[r] == 0) ++report.islands;
        if (masses[i].flags & RUBBLE_BODY_ASLEEP) {
            ++st.asleep[r];
        } else {
            ++st.awake[r];
            st.islandRestless[r] += st.restless[i];
            st.islandSlowFor[r] = std::min(st.islandSlowFor[r], st.slowFor[i]);
        }
    }

    // Put the islands slow for long enough to sleep; wake the sleeping bodies of the others if
    // something restless touches them. A slow body touching a sleeping one leaves it asleep (it
    // is as heavy as the ground meanwhile): a contact that comes and goes at rest must not wake
    // and sleep an island over and over.
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!isDynamic(masses[i])) continue;
        const std::uint32_t r = st.islands.find(i);
        const bool asleep = (masses[i].flags & RUBBLE_BODY_ASLEEP) != 0;
        if (st.awake[r] > 0) {
            if (st.islandSlowFor[r] >= kTimeToSleep) {
                if (!asleep) ++report.fellAsleep;
                masses[i].flags |= RUBBLE_BODY_ASLEEP;
                st.group[i] = r;
                velocities[i] = shared::BodyVelocity{};
                momenta[i] = shared::BodyMomentum{};
            } else if (asleep && st.islandRestless[r] > 0) {
                ++report.woken;
                masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
                st.slowFor[i] = 0.0f;
                st.group[i] = kNoGroup;
            }
        }
        st.wasAsleep[i] = (masses[i].flags & RUBBLE_BODY_ASLEEP) ? 1 : 0;
        if (st.wasAsleep[i])
            ++report.asleepBodies;
        else
            st.group[i] = kNoGroup;
    }
    return report;
}

} // namespace rubble
