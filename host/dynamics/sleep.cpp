// host/dynamics/sleep.cpp: stages wakeTouched and sleepBodies on the CPU; twins of
// kernels/sleep.cl.
#include "host/dynamics/sleep.h"

#include "rubble/shared/sleep.h"

namespace rubble {

using namespace shared;

std::uint32_t wakeTouched(std::span<const ParticleContact> contacts,
                          std::span<const BodyVelocity> approach, std::span<BodyMass> masses,
                          BodySleepState& state) {
    state.slowFor.resize(masses.size(), 0.0f);
    state.restless.resize(masses.size(), 0u);
    std::uint32_t woken = 0;
    for (const ParticleContact& c : contacts) {
        const uint fa = masses[c.a].flags, fb = masses[c.b].flags;
        std::uint32_t wake = RUBBLE_NO_BODY;
        if (wakesBeforeSolveItem(fa, fb, approach[c.b])) wake = c.a;
        if (wakesBeforeSolveItem(fb, fa, approach[c.a])) wake = c.b;
        if (wake == RUBBLE_NO_BODY) continue;
        masses[wake].flags &= ~RUBBLE_BODY_ASLEEP;
        state.slowFor[wake] = 0.0f;
        ++woken;
    }
    return woken;
}

BodySleepCounts sleepBodies(std::span<const ContactRow> rows, std::span<BodyMass> masses,
                            std::span<BodyVelocity> velocities, std::span<BodyMomentum> momenta,
                            float dt, BodySleepState& state) {
    const std::size_t n = masses.size();
    state.slowFor.resize(n, 0.0f);
    state.restless.resize(n, 0u);
    const uint fixed = RUBBLE_BODY_STATIC | RUBBLE_BODY_KINEMATIC;
    for (const ContactRow& r : rows) {
        const uint fa = masses[r.a].flags, fb = masses[r.b].flags;
        if (!(fa & fixed)) state.restless[r.a] |= restlessFromContactItem(fa, fb, velocities[r.b]);
        if (!(fb & fixed)) state.restless[r.b] |= restlessFromContactItem(fb, fa, velocities[r.a]);
    }
    BodySleepCounts counts;
    for (std::size_t i = 0; i < n; ++i) {
        if (masses[i].flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_KINEMATIC)) continue;
        const SleepRecord s{masses[i].flags, state.slowFor[i]};
        const SleepRecord next = sleepItem(s, state.restless[i], slowBodyItem(velocities[i]), dt);
        if ((next.flags & RUBBLE_BODY_ASLEEP) && !(s.flags & RUBBLE_BODY_ASLEEP)) {
            velocities[i] = BodyVelocity{};
            momenta[i] = BodyMomentum{};
        }
        if (!(next.flags & RUBBLE_BODY_ASLEEP) && (s.flags & RUBBLE_BODY_ASLEEP)) ++counts.woken;
        if (next.flags & RUBBLE_BODY_ASLEEP) ++counts.asleep;
        masses[i].flags = next.flags;
        state.slowFor[i] = next.slowFor;
        state.restless[i] = 0u;
    }
    return counts;
}

} // namespace rubble
