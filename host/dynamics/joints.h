// host/dynamics/joints.h: ball-and-socket and hinge joints in body frames and their velocity
// blocks for CPU stages 5 and 6; host/dynamics/joint_positions projects their poses.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "host/collision/contact.h"
#include "host/dynamics/solver_bodies.h"
#include "rubble/scene.h"
#include "rubble/shared/body.h"
#include "rubble/shared/pgs_joint.h"

namespace rubble {

/// A joint in the bodies' frames, with its rows of the current step and its accumulated
/// impulses. Point rows: C = (x_b + r_b) - (x_a + r_a) = 0, solved as one 3x3 block. Hinge rows:
/// C = (a_1 . b_2, a_1 . c_2) = 0 with a_1 the axis fixed in a, and b_2, c_2 perpendicular to the
/// axis fixed in b, solved as one 2x2 block (Chappuis 2013; Cline 2002).
struct Joint {
    JointType type = JointType::Ball;
    std::uint32_t a = 0, b = 0;
    glm::vec3 anchorA{0.0f}, anchorB{0.0f}; ///< the anchor in each body's frame, m
    glm::vec3 axisA{1, 0, 0};               ///< hinge axis in a's frame, unit
    glm::vec3 perpB[2];                     ///< unit, perpendicular to the axis, in b's frame

    // This step's rows (world frame), from prepareJoints.
    bool active = false;          ///< false when neither body moves in the solve
    glm::vec3 ra{0.0f}, rb{0.0f}; ///< centres of mass to the anchor, m
    glm::mat3 pointMass{0.0f};    ///< (J M^-1 J^T)^-1 of the point rows, kg
    float dt = 0.0f;              ///< the step the rows look across, s
    glm::vec3 turn[2];            ///< a_1 x b_2, a_1 x c_2: the hinge rows' angular Jacobian on a
    glm::mat2 turnMass{0.0f};     ///< (J M^-1 J^T)^-1 of the hinge rows, kg m^2

    // Accumulated impulses, kept between steps for warm starting.
    glm::vec3 pointImpulse{0.0f}; ///< on b at the anchor (a gets the opposite), N s
    glm::vec2 turnImpulse{0.0f};  ///< along turn[0], turn[1] on a (b gets the opposite), N m s
};

/// Joints from their scene descriptions at the initial poses (anchor and axis in world space).
std::vector<Joint> makeJoints(std::span<const JointDesc> descs,
                              std::span<const shared::BodyPose> poses);

/// A joint as the shared rows (rubble/shared/pgs_joint.h) and the device take it.
shared::PgsJoint sharedJoint(const Joint& j);

/// The joined body pairs, (min, max), sorted and unique: they do not collide.
std::vector<BodyPair> joinedPairs(std::span<const JointDesc> joints);

/// Stage buildContactRows for joints: world offsets, effective masses of both blocks at the
/// current poses; impulses are zeroed without warm starting.
/// reads: poses, bodies (inverse masses)   writes: joints' rows
void prepareJoints(std::span<Joint> joints, std::span<const shared::BodyPose> poses,
                   const SolverBodies& bodies, bool warmStart, float dt);

/// Applies the joints' accumulated impulses (warm start). writes: bodies' velocities
void warmStartJoints(std::span<const Joint> joints, SolverBodies& bodies);

/// One Gauss-Seidel update of a joint's blocks towards C' = 0 (the position error is left to
/// correctJointPositions); the change is scaled by relaxation. Returns the largest |impulse
/// change|, N s. writes: bodies' velocities, the joint's impulses
float solveJointVelocity(Joint& joint, SolverBodies& bodies, float relaxation);

/// Anchor separation (m) and hinge axis misalignment (rad) of one joint at the given poses.
void jointError(const Joint& joint, std::span<const shared::BodyPose> poses, float& linear,
                float& angular);

} // namespace rubble
