// host/scene/ragdoll.h: the ten-part ragdoll of the `ragdoll` scene generator (SCENE_FORMAT.md;
// physics report section 5.3): ten boxes joined by ball joints and hinges.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rubble/scene.h"

namespace rubble {

/// What the generator entry says.
struct RagdollSpec {
    std::string prefix = "ragdoll"; ///< body names are `<prefix>_chest` and so on
    std::string where;              ///< `file: generators[2]`, for errors
    glm::vec3 position{0.0f};       ///< the chest's centre, world, m
    float scale = 1.0f;             ///< lengths scale by this, masses by its cube
    std::uint32_t material = 0;     ///< index into Scene::materials
    bool debris = false;
};

/// A ragdoll's parts, indexed among themselves: a body's `shape` indexes `shapes`, a joint's `a`
/// and `b` index `bodies`; the scene loader offsets them.
struct RagdollParts {
    std::vector<ShapeDesc> shapes;
    std::vector<BodyDesc> bodies;
    std::vector<JointDesc> joints;
};

/// Builds a ragdoll standing upright in a T-pose, facing +z, about 1.8 m tall and 70 kg at
/// scale 1: chest, head, upper arms, forearms, thighs, shins (in that order, left before
/// right; left is +x); ball joints at the neck, shoulders and hips, hinges at the elbows (y axis)
/// and knees (x axis). Every part is a box; neighbouring parts leave a small gap around each
/// joint.
RagdollParts buildRagdoll(const RagdollSpec& spec);

} // namespace rubble
