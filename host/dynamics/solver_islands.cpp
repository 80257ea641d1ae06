// host/dynamics/solver_islands.cpp: a solver's islands and sleep over the body arrays.
#include "host/dynamics/solver_islands.h"

namespace rubble {

void SolverIslands::prepareRadii(const SolverScene& scene, BodiesView bodies) {
    if (radii_.size() == bodies.count()) return;
    radii_.resize(bodies.count());
    for (std::uint32_t i = 0; i < bodies.count(); ++i)
        radii_[i] = scene.shapes[bodies.shapeOf[i]].boundingRadius;
}

bool SolverIslands::wake(const SolverScene& scene, Bodies bodies,
                         std::span<const shared::BodyVelocity> approach,
                         std::span<const Manifold> manifolds) {
    prepareRadii(scene, bodies);
    return wakeIslands(manifolds, scene.joined, radii_, bodies.masses, approach, state_) > 0;
}

std::uint32_t SolverIslands::sleep(const SolverScene& scene, Bodies bodies,
                                   std::span<const Manifold> manifolds, float dt) {
    prepareRadii(scene, bodies);
    return updateSleep(manifolds, scene.joined, radii_, bodies.masses, bodies.velocities,
                       bodies.momenta, dt, state_)
        .asleepBodies;
}

} // namespace rubble
