// host/dynamics/sleep.h: sleeping as the device does it (stages wakeTouched and sleepBodies), the
// CPU twins of kernels/sleep.cl (dispatch in host/gpu/sleep.cpp) with the per-element math of
// rubble/shared/sleep.h: each contact row tells its bodies whether a neighbour is restless or
// fast, then each dynamic body updates its sleep. The reference pipeline's PGS sleeps by islands
// instead (host/dynamics/islands.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rubble/shared/contact_row.h"

namespace rubble {

/// Per body: how long it has been slow (s) and this step's restless marks.
struct BodySleepState {
    std::vector<float> slowFor;
    std::vector<std::uint32_t> restless;
};

/// What a step of sleepBodies did.
struct BodySleepCounts {
    std::uint32_t asleep = 0; ///< bodies asleep after it
    std::uint32_t woken = 0;  ///< bodies it woke
};

/// Stage wakeTouched, before the rows: a contact of a sleeping body with a waking one
/// (wakesBeforeSolveItem, on `approach`, the velocities before this step's forces) wakes it, its
/// slow time starting again, so that its mass takes part in this step's solve. Its own contacts
/// appear from the next step on (its particles tested none while it slept). Returns the bodies
/// it woke. reads: contacts, approach, masses (flags)   writes: masses (flags), state.slowFor
std::uint32_t wakeTouched(std::span<const shared::ParticleContact> contacts,
                          std::span<const shared::BodyVelocity> approach,
                          std::span<shared::BodyMass> masses, BodySleepState& state);

/// Stage sleepBodies: restless marks from every row (restlessFromContactItem on each side), then
/// sleepItem for every dynamic body; a body that falls asleep has its velocities and momenta
/// zeroed. reads: rows, velocities, masses (flags)   writes: masses (flags), velocities, momenta,
/// state
BodySleepCounts sleepBodies(std::span<const shared::ContactRow> rows,
                            std::span<shared::BodyMass> masses,
                            std::span<shared::BodyVelocity> velocities,
                            std::span<shared::BodyMomentum> momenta, float dt,
                            BodySleepState& state);

} // namespace rubble
