// host/dynamics/forces.h: CPU stage 1, applyForces: scene events due this step. Gravity is added
// with the momenta (core/integrate), user forces come through the World API.
#pragma once

#include <span>

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

} // namespace rubble
