// host/dynamics/forces.cpp: explosions as radial impulses on the momenta.
#include "host/dynamics/forces.h"

#include "host/core/math.h"

namespace rubble {

std::size_t applyExplosion(const EventDesc& e, std::span<const shared::BodyPose> poses,
                           std::span<shared::BodyMass> masses,
                           std::span<shared::BodyMomentum> momenta) {
    std::size_t reached = 0;
    for (std::size_t i = 0; i < poses.size(); ++i) {
        if (masses[i].inverseMass == 0.0f) continue;
        const glm::vec3 offset = toVec3(poses[i].position) - e.centre;
        const float d = glm::length(offset);
        if (d >= e.radius) continue;
        const glm::vec3 away = d > 0.0f ? offset / d : glm::vec3(0.0f, 1.0f, 0.0f);
        const glm::vec3 impulse = away * (e.impulse * (1.0f - d / e.radius));
        momenta[i].linear = toFloat4(toVec3(momenta[i].linear) + impulse);
        masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
        ++reached;
    }
    return reached;
}

} // namespace rubble
