// host/dynamics/soft_step_solver.cpp: the soft-step solver's stages over the body arrays: rows,
// substeps (which move the bodies), and sleeping.
#include "host/dynamics/soft_step_solver.h"

#include <algorithm>

#include "host/core/math.h"

namespace rubble {

bool SoftStepSolver::wake(const SolverScene& scene, Bodies bodies,
                          std::span<const shared::BodyVelocity> approach,
                          const StepContacts& contacts, const StepParams&) {
    return cache_.islands.wake(scene, bodies, approach, contacts.manifolds);
}

void SoftStepSolver::buildRows(const SolverScene& scene, BodiesView bodies,
                               std::span<const shared::BodyVelocity> approach,
                               const StepContacts& contacts, const StepParams& params) {
    SoftStepCache& c = cache_;
    if (!c.jointsBuilt) {
        c.joints = makeJoints(scene.joints, bodies.poses);
        c.jointsBuilt = true;
    }
    gatherSolverMasses(bodies.masses, bodies.poses, c.bodies);
    gatherSolverVelocities(bodies.velocities, c.bodies);
    const SolverOptions& o = params.solver;
    const ContactRowSettings settings{params.dt, o.baumgarte, o.slop, o.warmStart,
                                      params.collision == CollisionMethod::Particles};
    buildContactRows(contacts.manifolds, bodies.poses, c.bodies, approach, scene.materials,
                     bodies.materialOf, scene.joined, c.impulses, settings, c.contacts);
    prepareSoftContacts(contacts.manifolds, c.contacts, bodies.poses, c.bodies, approach,
                        scene.materials, bodies.materialOf, scene.joined, c.points,
                        c.pointManifolds);
    // prepareJoints keeps the impulses (or zeroes them without warm start) and marks the joints
    // that move; the soft step computes its own arms and masses at each substep's poses.
    prepareJoints(c.joints, bodies.poses, c.bodies, o.warmStart, params.dt);
    c.start.assign(approach.begin(), approach.end());
    c.poses.pose.assign(bodies.poses.begin(), bodies.poses.end());
    c.poses.moved.assign(bodies.count(), Lanes{});
}

Status SoftStepSolver::solve(const SolverScene&, Bodies bodies,
                             std::span<const shared::BodyVelocity> before, const StepContacts&,
                             const StepParams& params) {
    SoftStepCache& c = cache_;
    const SoftStepSettings settings = makeSoftStepSettings(params.solver, params.dt);
    solveSoftStep(c.contacts, c.points, c.pointManifolds, c.joints, c.bodies, c.start, before,
                  settings, c.poses, c.packed, c.residuals);
    scatterSolverVelocities(c.bodies, bodies.velocities);
    storeContactImpulses(c.contacts, c.impulses, c.bodies, c.nextImpulses, c.impulseScratch);
    std::swap(c.impulses, c.nextImpulses);
    return {};
}

void SoftStepSolver::solvePositions(const SolverScene&, Bodies bodies, const StepParams&) {
    SoftStepCache& c = cache_;
    for (std::uint32_t i = 0; i < bodies.count(); ++i) {
        if (!c.bodies.moves(i)) continue;
        bodies.poses[i] = c.poses.pose[i];
        bodies.velocities[i] = shared::velocityFromMomentumItem(bodies.momenta[i], bodies.masses[i],
                                                                bodies.poses[i].orientation);
    }
}

std::uint32_t SoftStepSolver::sleep(const SolverScene& scene, Bodies bodies,
                                    const StepContacts& contacts, const StepParams& params) {
    return cache_.islands.sleep(scene, bodies, contacts.manifolds, params.dt);
}

void SoftStepSolver::bodiesChanged(std::span<const std::uint32_t> newIndex, BodiesView) {
    SoftStepCache& c = cache_;
    for (Joint& j : c.joints) {
        j.a = newIndex[j.a];
        j.b = newIndex[j.b];
    }
    c.impulses.clear();
    c.islands.reset();
}

} // namespace rubble
