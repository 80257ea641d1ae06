// host/gpu/joints.h: a world's joints on the device (kernels/pgs_joints.cl, and their rows in
// the sweeps): in body frames once per world, their rows and impulses kept between steps, the
// jointed bodies' groups (which sleep and wake as one), and the projection's direct groups and
// coloring. The CPU twin is the joint part of PgsSolver (host/dynamics/).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/gpu/coloring.h"
#include "host/gpu/device_bodies.h"
#include "rubble/shared/pgs_joint.h"

namespace rubble::gpu {

struct DeviceJoints {
    std::uint32_t count = 0, bodyCount = 0, groupCount = 0;
    Buffer joints;     ///< PgsJoint per joint
    Buffer rows;       ///< PgsJointRow per joint: this step's, with the kept impulses
    Buffer bodies;     ///< the jointed bodies
    Buffer groupOf;    ///< per jointed body: its joint group (RUBBLE_NO_GROUP: not dynamic)
    Buffer groupVotes; ///< per joint group: a member stays awake (1), a member is awake (2)
    // The position projection: joint groups of at most RUBBLE_JOINT_DIRECT_ROWS rows solved as
    // one (JointGroup records, their members, their scratch); the joints of larger groups joint
    // by joint over `coloring` (`order`).
    std::uint32_t directGroupCount = 0;
    /// Totals over the directly projected groups: members, rows, and floats of their matrices
    /// (for the byte counts, host/gpu/traffic.cpp).
    std::uint32_t directMemberCount = 0, directRowCount = 0, directMatrixCount = 0;
    Buffer directGroups, groupMembers, positionRows, positionMatrix, positionSolution;
    Buffer deltaPosition, deltaRotation; ///< per body, zero between uses
    Buffer order, moved;
    Coloring coloring;
    std::vector<shared::PgsJoint> host;
    /// Per joint: whether each body is dynamic and not stepped by the host.
    std::vector<std::uint8_t> dynamicA, dynamicB;

    /// Errors: Device.
    Status create(StageQueue& q, std::span<const shared::PgsJoint> joints, BodiesView bodies,
                  std::span<const std::uint8_t> kinematic);
    /// This step's rows from the poses and the bodies' masses (`warmStart`: keep impulses).
    Status prepare(StageQueue& q, const DeviceBodies& b, bool warmStart, float dt);
    /// After the pushes: the joints projected onto their constraints (a direct group as one, up
    /// to RUBBLE_JOINT_POSITION_ITERATIONS Newton steps; larger groups joint by joint, color by
    /// color, as many sweeps); the jointed bodies' velocities follow.
    Status project(StageQueue& q, DeviceBodies& b);
};

} // namespace rubble::gpu
