// host/dynamics/pgs_solver.cpp: the reference pipeline's solver stages over the body arrays:
// contact and joint rows, PGS, the position corrections after integratePositions (contact push,
// joint projection), and sleeping.
#include "host/dynamics/pgs_solver.h"

#include "host/core/math.h"
#include "host/dynamics/pgs.h"

namespace rubble {

bool PgsSolver::wake(const SolverScene& scene, Bodies bodies,
                     std::span<const shared::BodyVelocity> approach, const StepContacts& contacts,
                     const StepParams&) {
    return cache_.islands.wake(scene, bodies, approach, contacts.manifolds);
}

void PgsSolver::buildRows(const SolverScene& scene, BodiesView bodies,
                          std::span<const shared::BodyVelocity> approach,
                          const StepContacts& contacts, const StepParams& params) {
    SolverCache& c = cache_;
    // Joints are turned into body frames at the poses of the first step.
    if (!c.jointsBuilt) {
        c.joints = makeJoints(scene.joints, bodies.poses);
        c.jointGroups = groupJoints(c.joints, bodies.masses);
        c.jointsBuilt = true;
    }
    gatherSolverMasses(bodies.masses, bodies.poses, c.bodies);
    gatherSolverVelocities(bodies.velocities, c.bodies);
    const SolverOptions& o = params.solver;
    const ContactRowSettings settings{params.dt, o.baumgarte, o.slop, o.warmStart,
                                      params.collision == CollisionMethod::Particles};
    buildContactRows(contacts.manifolds, bodies.poses, c.bodies, approach, scene.materials,
                     bodies.materialOf, scene.joined, c.impulses, settings, c.contacts);
    prepareJoints(c.joints, bodies.poses, c.bodies, o.warmStart, params.dt);
}

Status PgsSolver::solve(const SolverScene&, Bodies bodies, std::span<const shared::BodyVelocity>,
                        const StepContacts&, const StepParams& params) {
    SolverCache& c = cache_;
    solvePgs(c.contacts, c.joints, c.bodies, params.solver, c.residuals);
    c.pushed =
        solvePushes(c.contacts, c.bodies, params.solver.iterations, params.solver.relaxation);
    scatterSolverVelocities(c.bodies, bodies.velocities);
    storeContactImpulses(c.contacts, c.impulses, c.bodies, c.nextImpulses, c.impulseScratch);
    std::swap(c.impulses, c.nextImpulses);
    return {};
}

void PgsSolver::solvePositions(const SolverScene&, Bodies bodies, const StepParams& params) {
    SolverCache& c = cache_;
    const float dt = params.dt;
    // Bounces leave from the contact the bodies reached, with momenta to match.
    if (solveRestitution(c.contacts, c.bodies, params.solver.iterations)) {
        addBounceImpulses(c.contacts, bodies.momenta);
        for (std::uint32_t i = 0; i < bodies.count(); ++i)
            if (c.bodies.moves(i))
                bodies.velocities[i] = shared::velocityFromMomentumItem(
                    bodies.momenta[i], bodies.masses[i], bodies.poses[i].orientation);
    }
    // Contacts: the split position pass moves the bodies out of each other.
    if (c.pushed) {
        for (std::uint32_t i = 0; i < bodies.count(); ++i) {
            const SolverVelocity& p = c.bodies.push[i];
            if (!c.bodies.moves(i)) continue;
            shared::BodyPose& pose = bodies.poses[i];
            pose.position = toFloat4(toVec3(pose.position) + fromLanes(p.linear) * dt);
            pose.orientation =
                shared::quatIntegrate(pose.orientation, toFloat4(fromLanes(p.angular)), dt);
            bodies.velocities[i] = shared::velocityFromMomentumItem(
                bodies.momenta[i], bodies.masses[i], pose.orientation);
        }
    }
    if (c.joints.empty()) return;
    // Joints: projected onto their constraints.
    c.jointPositions = correctJointPositions(c.joints, c.jointGroups, bodies.masses, bodies.poses,
                                             kJointPositionIterations, c.jointScratch);
    // The turned bodies' angular velocities follow from their momenta at the new orientations.
    for (const Joint& j : c.joints)
        for (const std::uint32_t i : {j.a, j.b})
            if (isAwakeDynamic(bodies.masses[i]))
                bodies.velocities[i] = shared::velocityFromMomentumItem(
                    bodies.momenta[i], bodies.masses[i], bodies.poses[i].orientation);
}

std::uint32_t PgsSolver::sleep(const SolverScene& scene, Bodies bodies,
                               const StepContacts& contacts, const StepParams& params) {
    return cache_.islands.sleep(scene, bodies, contacts.manifolds, params.dt);
}

void PgsSolver::bodiesChanged(std::span<const std::uint32_t> newIndex, BodiesView bodies) {
    SolverCache& c = cache_;
    // The joints name bodies by index; none of a joint's bodies is ever removed.
    for (Joint& j : c.joints) {
        j.a = newIndex[j.a];
        j.b = newIndex[j.b];
    }
    if (c.jointsBuilt) c.jointGroups = groupJoints(c.joints, bodies.masses);
    c.impulses.clear();
    c.islands.reset();
}

} // namespace rubble
