// host/dynamics/solver_bodies.cpp: body arrays in and out of the constraint solver (stages 5, 6).
#include "host/dynamics/solver_bodies.h"

#include "host/core/assert.h"
#include "host/core/math.h"

namespace rubble {

void gatherSolverMasses(std::span<const shared::BodyMass> masses,
                        std::span<const shared::BodyPose> poses, SolverBodies& bodies) {
    RUBBLE_ASSERT(masses.size() == poses.size());
    const std::size_t n = masses.size();
    bodies.inverseMass.resize(n);
    bodies.inverseInertia.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!isAwakeDynamic(masses[i])) {
            bodies.inverseMass[i] = 0.0f;
            bodies.inverseInertia[i] = glm::mat3(0.0f);
            continue;
        }
        bodies.inverseMass[i] = masses[i].inverseMass;
        bodies.inverseInertia[i] =
            toMat3(shared::inverseInertiaWorldItem(masses[i], poses[i].orientation));
    }
}

void gatherSolverVelocities(std::span<const shared::BodyVelocity> velocities,
                            SolverBodies& bodies) {
    const std::size_t n = velocities.size();
    bodies.velocity.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        bodies.velocity[i].linear = toLanes(toVec3(velocities[i].linear));
        bodies.velocity[i].angular = toLanes(toVec3(velocities[i].angular));
    }
}

void scatterSolverVelocities(const SolverBodies& bodies,
                             std::span<shared::BodyVelocity> velocities) {
    RUBBLE_ASSERT(velocities.size() == bodies.velocity.size());
    for (std::size_t i = 0; i < velocities.size(); ++i) {
        if (!bodies.moves(std::uint32_t(i))) continue;
        velocities[i].linear = toFloat4(fromLanes(bodies.velocity[i].linear));
        velocities[i].angular = toFloat4(fromLanes(bodies.velocity[i].angular));
    }
}

} // namespace rubble
