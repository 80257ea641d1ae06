// host/core/integrate.cpp: CPU stages 2 and 7; twins of kernels/integrate.cl.
#include "host/core/integrate.h"

#include "host/core/assert.h"

namespace rubble {

using namespace shared;

void integrateVelocities(std::span<BodyMomentum> momenta, std::span<const BodyForce> forces,
                         std::span<const BodyMass> masses, std::span<const BodyPose> poses,
                         std::span<BodyVelocity> velocities, std::span<BodyVelocity> beforeForces,
                         float4 gravity, float dt) {
    RUBBLE_ASSERT(momenta.size() == forces.size() && momenta.size() == masses.size() &&
                  momenta.size() == poses.size() && momenta.size() == velocities.size() &&
                  momenta.size() == beforeForces.size());
    for (std::size_t i = 0; i < momenta.size(); ++i) {
        // A kinematic body keeps the velocities it was given: no force moves it.
        if (masses[i].flags & RUBBLE_BODY_KINEMATIC) {
            beforeForces[i] = velocities[i];
            continue;
        }
        beforeForces[i] = beforeForcesItem(momenta[i], masses[i], velocities[i]);
        if (masses[i].flags & RUBBLE_BODY_ASLEEP) continue;
        momenta[i] = integrateMomentumItem(momenta[i], forces[i], masses[i], gravity, dt);
        velocities[i] = velocityFromMomentumItem(momenta[i], masses[i], poses[i].orientation);
    }
}

void absorbVelocityChange(std::span<BodyMomentum> momenta, std::span<const BodyVelocity> before,
                          std::span<const BodyVelocity> after, std::span<const BodyMass> masses,
                          std::span<const BodyPose> poses) {
    RUBBLE_ASSERT(momenta.size() == before.size() && momenta.size() == after.size());
    for (std::size_t i = 0; i < momenta.size(); ++i)
        momenta[i] = absorbVelocityChangeItem(momenta[i], before[i], after[i], masses[i],
                                              poses[i].orientation);
}

void integratePositions(std::span<BodyPose> poses, std::span<BodyVelocity> velocities,
                        std::span<const BodyVelocity> atStart, std::span<const BodyMomentum> momenta,
                        std::span<const BodyMass> masses, float dt, bool symplectic) {
    RUBBLE_ASSERT(poses.size() == velocities.size() && poses.size() == momenta.size());
    RUBBLE_ASSERT(symplectic || atStart.size() == poses.size());
    for (std::size_t i = 0; i < poses.size(); ++i) {
        // A kinematic body moves with its own velocities, which nothing changes.
        if (masses[i].flags & RUBBLE_BODY_KINEMATIC) {
            poses[i] = integratePositionItem(poses[i], velocities[i], dt);
            continue;
        }
        if (masses[i].inverseMass == 0.0f || (masses[i].flags & RUBBLE_BODY_ASLEEP)) continue;
        poses[i] = symplectic ? integratePositionSymplecticItem(poses[i], velocities[i], momenta[i],
                                                                masses[i], dt)
                              : integratePositionItem(poses[i], atStart[i], dt);
        velocities[i] = velocityFromMomentumItem(momenta[i], masses[i], poses[i].orientation);
    }
}

} // namespace rubble
