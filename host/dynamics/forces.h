// host/dynamics/forces.h: CPU stage 1, applyForces: scene events due this step. Gravity is added
// with the momenta (core/integrate), user forces come through the World API.
#pragma once

#include <cstdint>
#include <span>

#include "host/core/bodies.h"
#include "rubble/scene.h"
#include "rubble/shared/body.h"

namespace rubble {

/// Adds an explosion's impulse, impulse * (1 - d / radius) N s away from the centre at the centre
/// of mass, to every dynamic body within the radius (a body exactly at the centre goes up), and
/// wakes it. Returns how many bodies it reached.
/// reads: poses, masses   writes: momenta, masses (flags)
std::size_t applyExplosion(const EventDesc& explosion, std::span<const shared::BodyPose> poses,
                           std::span<shared::BodyMass> masses,
                           std::span<shared::BodyMomentum> momenta);

/// Whether an event that has not fired is due in a step that starts at `time`, s.
inline bool eventDue(const EventDesc& e, std::uint8_t fired, double time) {
    return !fired && time + 1e-9 >= double(e.time);
}

/// Stage applyForces: every explosion due at `time` (s) acts on the bodies and is marked fired.
/// reads: events, poses, masses   writes: fired, momenta, masses (flags)
void applyDueExplosions(std::span<const EventDesc> events, std::span<std::uint8_t> fired,
                        double time, Bodies bodies);

} // namespace rubble
