// host/world/world_build.h: adding one body of a scene to a world's arrays (World::create, and
// World::addDebris later on).
#pragma once

#include "host/core/bodies.h"
#include "host/geometry/shape.h"
#include "rubble/scene.h"

namespace rubble {

struct WorldState;

/// A body's momenta from its velocities (world frame): P = m v, L = I_w omega.
shared::BodyMomentum momentumFromVelocity(const shared::BodyMass& mass,
                                          const shared::BodyPose& pose, glm::vec3 linear,
                                          glm::vec3 angular);

/// Appends a body's entries to the body arrays: its mass from `mass` or `density` and `shape`
/// (static bodies get none), momenta from its velocities, no force. The shape and material
/// indices are taken as given.
void appendBodyArrays(BodyArrays& bodies, const BodyDesc& b, const Shape& shape);

/// Appends a body to every per-body array: its mass from `mass` or `density` and its shape
/// (static bodies get none), momenta from its velocities, no force. The shape and material
/// indices must be valid.
void appendBody(WorldState& s, const BodyDesc& b);

} // namespace rubble
