// host/dynamics/joint_positions.h: the joints' position correction after stage 7: each connected
// group of joints is projected back onto its constraints by Newton steps on the poses, with the
// group's whole system solved directly (Cholesky), or joint by joint when the group is large.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "host/dynamics/joints.h"
#include "rubble/shared/body.h"
#include "rubble/shared/pgs_joint.h"

namespace rubble {

/// Joints grouped by the moving bodies they share (static bodies connect nothing): joints of
/// group g are members[start[g] .. start[g + 1]), by joint index.
struct JointGroups {
    std::vector<std::uint32_t> start;
    std::vector<std::uint32_t> members;
};

/// Groups the joints; `masses` says which bodies are static.
JointGroups groupJoints(std::span<const Joint> joints, std::span<const shared::BodyMass> masses);

/// One constraint row at the current poses: C and its Jacobian, and M^-1 J^T.
struct PositionRow {
    std::uint32_t a = 0, b = 0;
    float error = 0;                         ///< C: m for point rows, the cosine for hinge rows
    glm::vec3 linearA{0.0f}, angularA{0.0f}; ///< J on a (position, rotation vector)
    glm::vec3 linearB{0.0f}, angularB{0.0f}; ///< J on b
    glm::vec3 moveA{0.0f}, turnA{0.0f};      ///< m_a^-1 J_lin, I_a^-1 J_ang
    glm::vec3 moveB{0.0f}, turnB{0.0f};
};

/// Buffers reused from step to step.
struct JointPositionScratch {
    std::vector<PositionRow> rows;
    std::vector<double> matrix, solution;
    std::vector<glm::vec3> deltaPosition, deltaRotation; ///< per body, zero between uses
};

/// Outcome of a position correction.
struct JointPositionReport {
    float linearErrorBefore = 0; ///< largest anchor separation before the correction, m
    float linearErrorAfter = 0;  ///< after it, m
    float angularErrorAfter = 0; ///< largest hinge axis misalignment after it, rad
    int iterations = 0;          ///< most Newton steps any group took
};

/// Groups with more rows than this are corrected joint by joint (non-linear Gauss-Seidel).
/// (RUBBLE_JOINT_DIRECT_ROWS: the device draws the line in the same place.)
inline constexpr std::size_t kDirectRowLimit = RUBBLE_JOINT_DIRECT_ROWS;

/// Position correction after integratePositions (Catto, "Modeling and Solving Constraints",
/// GDC 2009, position projection; the whole group at once as in Baraff, "Linear-Time Dynamics
/// using Lagrange Multipliers", SIGGRAPH 1996): lambda = -(J M^-1 J^T)^-1 C at the current poses,
/// x += M^-1 J^T lambda, repeated until every joint of the group is within tolerance or
/// maxIterations steps have run. Only awake dynamic bodies move; velocities are untouched.
/// reads: joints, groups, masses   writes: poses
JointPositionReport correctJointPositions(std::span<const Joint> joints, const JointGroups& groups,
                                          std::span<const shared::BodyMass> masses,
                                          std::span<shared::BodyPose> poses, int maxIterations,
                                          JointPositionScratch& scratch);

} // namespace rubble
