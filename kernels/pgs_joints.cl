// kernels/pgs_joints.cl: entry points for the joints of projected Gauss-Seidel on the device:
// their velocity rows (prepareJoints) and their position projection after integratePositions
// (projectJointGroups, projectJoints, jointVelocities). The math is in rubble/shared/pgs_joint.h;
// the CPU twin is host/dynamics/joint_positions.cpp.
#include "rubble/shared/body.h"
#include "rubble/shared/pgs_joint.h"

// Stage buildContactRows for joints (prepareJoints): one work-item per joint.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
prepareJoints(const uint count, __global const PgsJoint* joints, __global const BodyPose* poses,
              __global const JacobiBody* bodies, const uint warmStart, const float dt,
              __global PgsJointRow* jointRows) {
    const uint j = get_global_id(0);
    if (j >= count) return;
    const PgsJoint joint = joints[j];
    jointRows[j] = prepareJointItem(joint, jointRows[j], poses[joint.a], poses[joint.b],
                                    bodies[joint.a], bodies[joint.b], (int)warmStart, dt);
}

// The joints' position projection of the groups solved as one (the CPU path's direct
// correction), one work-item per group: projectJointGroupItem on the group's scratch.
__kernel void projectJointGroups(const uint count, __global const JointGroup* groups,
                                 __global const uint* members, __global const PgsJoint* joints,
                                 __global const BodyMass* masses, __global const uint* flags,
                                 __global BodyPose* poses, __global JointPositionRow* rows,
                                 __global JointReal* matrix, __global JointReal* solution,
                                 __global float4* deltaPosition, __global float4* deltaRotation,
                                 const int iterations) {
    const uint g = get_global_id(0);
    if (g >= count) return;
    const JointGroup group = groups[g];
    projectJointGroupItem(members + group.first, group.count, joints, masses, flags, poses,
                          rows + group.rowStart, matrix + group.matrixStart,
                          solution + group.rowStart, deltaPosition, deltaRotation, iterations);
}

// One sweep of the joints' position projection, one color of joints (no two share a dynamic
// body): each joint one Newton step onto its constraints (projectJointItem). A sweep after one
// that moved nothing does nothing: every joint holds.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
projectJoints(const uint first, const uint count, __global const uint* order,
              __global const PgsJoint* joints, __global const BodyMass* masses,
              __global const uint* flags, __global BodyPose* poses, const uint sweep,
              __global uint* sweepMoved) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    if (sweep > 0u && sweepMoved[sweep - 1u] == 0u) return;
    const PgsJoint joint = joints[order[first + i]];
    const BodyPose pa = poses[joint.a], pb = poses[joint.b];
    int moved = 0;
    const PosePair out =
        projectJointItem(joint, pa, pb, projectionBodyItem(masses[joint.a], flags[joint.a], pa),
                         projectionBodyItem(masses[joint.b], flags[joint.b], pb), &moved);
    if (!moved) return;
    poses[joint.a] = out.a;
    poses[joint.b] = out.b;
    sweepMoved[sweep] = 1u;
}

// After the projection: the jointed bodies' angular velocities follow from their momenta at
// the new orientations (PgsSolver::solvePositions). One work-item per jointed body.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
jointVelocities(const uint count, __global const uint* jointBodies,
                __global const BodyMass* masses, __global const uint* flags,
                __global const BodyPose* poses, __global const BodyMomentum* momenta,
                __global BodyVelocity* velocities) {
    const uint k = get_global_id(0);
    if (k >= count) return;
    const uint i = jointBodies[k];
    const BodyMass m = masses[i];
    if (!activeBodyItem(flags[i]) || !(m.inverseMass > 0.0f)) return;
    velocities[i] = velocityFromMomentumItem(momenta[i], m, poses[i].orientation);
}
