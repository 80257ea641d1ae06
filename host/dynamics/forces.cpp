// host/dynamics/forces.cpp: explosions as radial impulses on the momenta.
#include "host/dynamics/forces.h"

#include "host/core/math.h"
#include "rubble/shared/events.h"

namespace rubble {

std::size_t applyExplosion(const EventDesc& e, std::span<const shared::BodyPose> poses,
                           std::span<shared::BodyMass> masses,
                           std::span<shared::BodyMomentum> momenta) {
    std::size_t reached = 0;
    const shared::float4 centre = toFloat4(e.centre);
    for (std::size_t i = 0; i < poses.size(); ++i) {
        if (masses[i].inverseMass == 0.0f) continue;
        // The device's kernel (kernels/forces.cl) computes the same impulse.
        const shared::float4 impulse =
            shared::explosionImpulseItem(poses[i].position, centre, e.impulse, e.radius);
        if (impulse.w == 0.0f) continue; // out of reach
        momenta[i].linear = shared::add4(momenta[i].linear,
                                         shared::vec4(impulse.x, impulse.y, impulse.z));
        masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
        ++reached;
    }
    return reached;
}

void applyDueExplosions(std::span<const EventDesc> events, std::span<std::uint8_t> fired,
                        double time, Bodies bodies) {
    for (std::size_t e = 0; e < events.size(); ++e) {
        if (!eventDue(events[e], fired[e], time)) continue;
        applyExplosion(events[e], bodies.poses, bodies.masses, bodies.momenta);
        fired[e] = 1;
    }
}

} // namespace rubble
