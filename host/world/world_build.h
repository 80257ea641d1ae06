// host/world/world_build.h: adding one body of a scene to a world's arrays (World::create, and
// World::addDebris later on).
#pragma once

#include "rubble/scene.h"

namespace rubble {

struct WorldState;

/// Appends a body to every per-body array: its mass from `mass` or `density` and its shape
/// (static bodies get none), momenta from its velocities, no force. The shape and material
/// indices must be valid.
void appendBody(WorldState& s, const BodyDesc& b);

} // namespace rubble
