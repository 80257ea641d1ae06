// host/dynamics/joints.cpp: ball and hinge joints: body frames, velocity blocks (stages 5, 6).
#include "host/dynamics/joints.h"

#include <algorithm>
#include <cmath>

#include "host/core/math.h"
#include "host/dynamics/contact_rows.h"
#include "host/dynamics/joint_rows.h"

namespace rubble {
namespace {

glm::vec3 rotate(const shared::BodyPose& pose, glm::vec3 v) {
    return toVec3(shared::quatRotate(pose.orientation, toFloat4(v)));
}
glm::vec3 rotateInverse(const shared::BodyPose& pose, glm::vec3 v) {
    return toVec3(shared::quatRotateInverse(pose.orientation, toFloat4(v)));
}

} // namespace

std::vector<Joint> makeJoints(std::span<const JointDesc> descs,
                              std::span<const shared::BodyPose> poses) {
    std::vector<Joint> joints;
    joints.reserve(descs.size());
    for (const JointDesc& d : descs) {
        Joint j;
        j.type = d.type;
        j.a = d.a;
        j.b = d.b;
        const shared::BodyPose& pa = poses[d.a];
        const shared::BodyPose& pb = poses[d.b];
        j.anchorA = rotateInverse(pa, d.anchor - toVec3(pa.position));
        j.anchorB = rotateInverse(pb, d.anchor - toVec3(pb.position));
        const glm::vec3 axis = glm::normalize(d.axis);
        j.axisA = rotateInverse(pa, axis);
        const glm::vec3 axisB = rotateInverse(pb, axis);
        tangentBasis(axisB, j.perpB[0], j.perpB[1]);
        joints.push_back(j);
    }
    return joints;
}

shared::PgsJoint sharedJoint(const Joint& j) {
    shared::PgsJoint d{};
    d.anchorA = toFloat4(j.anchorA);
    d.anchorB = toFloat4(j.anchorB);
    d.axisA = toFloat4(j.axisA);
    d.perpB[0] = toFloat4(j.perpB[0]);
    d.perpB[1] = toFloat4(j.perpB[1]);
    d.type = j.type == JointType::Hinge ? RUBBLE_JOINT_HINGE : RUBBLE_JOINT_BALL;
    d.a = j.a;
    d.b = j.b;
    return d;
}

std::vector<BodyPair> joinedPairs(std::span<const JointDesc> joints) {
    std::vector<BodyPair> pairs;
    pairs.reserve(joints.size());
    for (const JointDesc& j : joints) pairs.push_back({std::min(j.a, j.b), std::max(j.a, j.b)});
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    return pairs;
}

void prepareJoints(std::span<Joint> joints, std::span<const shared::BodyPose> poses,
                   const SolverBodies& bodies, bool warmStart, float dt) {
    for (Joint& j : joints) {
        j.active = bodies.moves(j.a) || bodies.moves(j.b);
        if (!warmStart || !j.active) {
            j.pointImpulse = glm::vec3(0.0f);
            j.turnImpulse = glm::vec2(0.0f);
        }
        if (!j.active) continue;
        const shared::BodyPose& pa = poses[j.a];
        const shared::BodyPose& pb = poses[j.b];
        const glm::mat3& ia = bodies.inverseInertia[j.a];
        const glm::mat3& ib = bodies.inverseInertia[j.b];
        j.ra = rotate(pa, j.anchorA);
        j.rb = rotate(pb, j.anchorB);
        j.pointMass = safeInverse(
            pointMatrix(j.ra, j.rb, bodies.inverseMass[j.a], bodies.inverseMass[j.b], ia, ib));
        j.dt = dt;
        if (j.type == JointType::Hinge) {
            hingeRows(j, pa, pb, j.turn, nullptr);
            j.turnMass = safeInverse(hingeMatrix(j.turn, ia, ib));
        }
    }
}

void warmStartJoints(std::span<const Joint> joints, SolverBodies& bodies) {
    for (const Joint& j : joints) {
        if (!j.active) continue;
        applyPointImpulse(j, j.ra, j.rb, j.pointImpulse, bodies);
        if (j.type == JointType::Hinge) applyTurnImpulse(j, j.turn, j.turnImpulse, bodies);
    }
}

float solveJointVelocity(Joint& j, SolverBodies& bodies, float relaxation) {
    if (!j.active) return 0.0f;
    float residual = 0.0f;
    if (j.type == JointType::Hinge) {
        const glm::vec3 dw =
            fromLanes(bodies.velocity[j.a].angular) - fromLanes(bodies.velocity[j.b].angular);
        const glm::vec2 speed(glm::dot(j.turn[0], dw), glm::dot(j.turn[1], dw));
        const glm::vec2 impulse = -(j.turnMass * speed) * relaxation;
        j.turnImpulse += impulse;
        applyTurnImpulse(j, j.turn, impulse, bodies);
        residual = std::max(std::abs(impulse.x), std::abs(impulse.y));
    }
    const SolverVelocity& a = bodies.velocity[j.a];
    const SolverVelocity& b = bodies.velocity[j.b];
    const glm::vec3 speed = (fromLanes(b.linear) + glm::cross(fromLanes(b.angular), j.rb)) -
                            (fromLanes(a.linear) + glm::cross(fromLanes(a.angular), j.ra));
    // The anchors part by the turns' second-order motion over the step: the rows ask for the
    // speed that brings them back together at its end, from the velocities as they are now.
    const glm::vec3 parting =
        toVec3(shared::turnSpeedItem(toFloat4(fromLanes(b.angular)), toFloat4(j.rb), j.dt)) -
        toVec3(shared::turnSpeedItem(toFloat4(fromLanes(a.angular)), toFloat4(j.ra), j.dt));
    const glm::vec3 impulse = -(j.pointMass * (speed + parting)) * relaxation;
    j.pointImpulse += impulse;
    applyPointImpulse(j, j.ra, j.rb, impulse, bodies);
    const glm::vec3 size = glm::abs(impulse);
    return std::max(residual, std::max(size.x, std::max(size.y, size.z)));
}

void jointError(const Joint& j, std::span<const shared::BodyPose> poses, float& linear,
                float& angular) {
    const shared::BodyPose& pa = poses[j.a];
    const shared::BodyPose& pb = poses[j.b];
    const glm::vec3 pointA = toVec3(pa.position) + rotate(pa, j.anchorA);
    const glm::vec3 pointB = toVec3(pb.position) + rotate(pb, j.anchorB);
    linear = glm::length(pointB - pointA);
    angular = 0.0f;
    if (j.type != JointType::Hinge) return;
    // The axis fixed in b is perpendicular to both of its perpendiculars.
    const glm::vec3 a1 = rotate(pa, j.axisA);
    const glm::vec3 a2 = glm::cross(rotate(pb, j.perpB[0]), rotate(pb, j.perpB[1]));
    angular = std::atan2(glm::length(glm::cross(a1, a2)), glm::dot(a1, a2));
}

} // namespace rubble
