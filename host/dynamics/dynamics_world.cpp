// host/dynamics/dynamics_world.cpp: CPU stages 5 and 6 over a world's arrays, the position
// corrections after stage 7 (contact push, joint projection), and sleeping.
#include "host/dynamics/dynamics_world.h"

#include "host/core/math.h"
#include "host/dynamics/pgs.h"
#include "host/world/world_state.h"

namespace rubble {

void runBuildContactRows(WorldState& s) {
    SolverCache& c = s.solver;
    // Joints are turned into body frames at the poses of the first step.
    if (!c.jointsBuilt) {
        c.joints = makeJoints(s.joints, s.poses);
        c.jointGroups = groupJoints(c.joints, s.masses);
        c.jointsBuilt = true;
    }
    gatherSolverMasses(s.masses, s.poses, c.bodies);
    gatherSolverVelocities(s.velocities, c.bodies);
    const SolverOptions& o = s.options.solver;
    const ContactRowSettings settings{s.options.dt, o.baumgarte, o.slop, o.warmStart};
    buildContactRows(s.manifolds, s.poses, c.bodies, s.velocitiesAtStart, s.materials, s.materialOf,
                     s.joined, c.impulses, settings, c.contacts);
    prepareJoints(c.joints, s.poses, c.bodies, o.warmStart);
}

void runSolveVelocities(WorldState& s) {
    SolverCache& c = s.solver;
    solvePgs(c.contacts, c.joints, c.bodies, s.options.solver, c.residuals);
    c.pushed =
        solvePushes(c.contacts, c.bodies, s.options.solver.iterations, s.options.solver.relaxation);
    scatterSolverVelocities(c.bodies, s.velocities);
    storeContactImpulses(c.contacts, c.impulses, c.bodies, c.nextImpulses, c.impulseScratch);
    std::swap(c.impulses, c.nextImpulses);
    s.stats.solverResidual = c.residuals.empty() ? 0.0f : c.residuals.back();
}

void runSolvePositions(WorldState& s) {
    SolverCache& c = s.solver;
    const float dt = s.options.dt;
    // Bounces leave from the contact the bodies reached, with momenta to match.
    if (solveRestitution(c.contacts, c.bodies, s.options.solver.iterations)) {
        addBounceImpulses(c.contacts, s.momenta);
        for (std::uint32_t i = 0; i < s.bodyCount(); ++i)
            if (c.bodies.moves(i))
                s.velocities[i] = shared::velocityFromMomentumItem(s.momenta[i], s.masses[i],
                                                                   s.poses[i].orientation);
    }
    // Contacts: the split position pass moves the bodies out of each other.
    if (c.pushed) {
        for (std::uint32_t i = 0; i < s.bodyCount(); ++i) {
            const SolverVelocity& p = c.bodies.push[i];
            if (!c.bodies.moves(i)) continue;
            BodyPose& pose = s.poses[i];
            pose.position = toFloat4(toVec3(pose.position) + fromLanes(p.linear) * dt);
            pose.orientation =
                shared::quatIntegrate(pose.orientation, toFloat4(fromLanes(p.angular)), dt);
            s.velocities[i] =
                shared::velocityFromMomentumItem(s.momenta[i], s.masses[i], pose.orientation);
        }
    }
    if (c.joints.empty()) return;
    // Joints: projected onto their constraints.
    c.jointPositions = correctJointPositions(c.joints, c.jointGroups, s.masses, s.poses,
                                             kJointPositionIterations, c.jointScratch);
    // The turned bodies' angular velocities follow from their momenta at the new orientations.
    for (const Joint& j : c.joints)
        for (const std::uint32_t i : {j.a, j.b})
            if (isAwakeDynamic(s.masses[i]))
                s.velocities[i] = shared::velocityFromMomentumItem(s.momenta[i], s.masses[i],
                                                                   s.poses[i].orientation);
}

void runUpdateSleep(WorldState& s) {
    SolverCache& c = s.solver;
    if (c.radii.size() != s.bodyCount()) {
        c.radii.resize(s.bodyCount());
        for (std::uint32_t i = 0; i < s.bodyCount(); ++i)
            c.radii[i] = s.shapes[s.shapeOf[i]].boundingRadius;
    }
    c.lastSleep = updateSleep(s.manifolds, c.joints, c.radii, s.masses, s.velocities, s.momenta,
                              s.options.dt, c.sleep);
}

} // namespace rubble
