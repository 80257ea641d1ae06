// host/dynamics/joints.cpp: ball and hinge joints: body frames, velocity blocks (stages 5, 6).
#include "host/dynamics/joints.h"

#include <algorithm>
#include <cmath>

#include "host/core/math.h"
#include "host/dynamics/contact_rows.h"

namespace rubble {
namespace {

// The cross-product matrix: skew(r) v = r x v (glm is column-major).
glm::mat3 skew(glm::vec3 r) {
    return glm::mat3(glm::vec3(0.0f, r.z, -r.y), glm::vec3(-r.z, 0.0f, r.x),
                     glm::vec3(r.y, -r.x, 0.0f));
}

// K of the point rows: (m_a^-1 + m_b^-1) 1 - [r_a] I_a^-1 [r_a] - [r_b] I_b^-1 [r_b].
glm::mat3 pointMatrix(glm::vec3 ra, glm::vec3 rb, float ima, float imb, const glm::mat3& ia,
                      const glm::mat3& ib) {
    const glm::mat3 sa = skew(ra), sb = skew(rb);
    return glm::mat3(ima + imb) - sa * ia * sa - sb * ib * sb;
}

// Inverse of a symmetric positive (semi-)definite matrix; zero when singular.
glm::mat3 safeInverse(const glm::mat3& k) {
    const float det = glm::determinant(k);
    return std::abs(det) > 1e-12f ? glm::inverse(k) : glm::mat3(0.0f);
}
glm::mat2 safeInverse(const glm::mat2& k) {
    const float det = glm::determinant(k);
    return std::abs(det) > 1e-12f ? glm::inverse(k) : glm::mat2(0.0f);
}

glm::vec3 rotate(const shared::BodyPose& pose, glm::vec3 v) {
    return toVec3(shared::quatRotate(pose.orientation, toFloat4(v)));
}
glm::vec3 rotateInverse(const shared::BodyPose& pose, glm::vec3 v) {
    return toVec3(shared::quatRotateInverse(pose.orientation, toFloat4(v)));
}

// The hinge rows' angular Jacobian on a: a_1 x b_2 and a_1 x c_2 at the given poses; the
// constraint values a_1 . b_2, a_1 . c_2 go to c when it is not null.
void hingeRows(const Joint& j, const shared::BodyPose& pa, const shared::BodyPose& pb,
               glm::vec3 turn[2], glm::vec2* c) {
    const glm::vec3 a1 = rotate(pa, j.axisA);
    const glm::vec3 b2 = rotate(pb, j.perpB[0]), c2 = rotate(pb, j.perpB[1]);
    turn[0] = glm::cross(a1, b2);
    turn[1] = glm::cross(a1, c2);
    if (c) *c = glm::vec2(glm::dot(a1, b2), glm::dot(a1, c2));
}

glm::mat2 hingeMatrix(const glm::vec3 turn[2], const glm::mat3& ia, const glm::mat3& ib) {
    const glm::mat3 sum = ia + ib;
    const float k00 = glm::dot(turn[0], sum * turn[0]);
    const float k01 = glm::dot(turn[0], sum * turn[1]);
    const float k11 = glm::dot(turn[1], sum * turn[1]);
    return glm::mat2(k00, k01, k01, k11);
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

namespace {

void applyPointImpulse(const Joint& j, glm::vec3 impulse, SolverBodies& bodies) {
    SolverVelocity& a = bodies.velocity[j.a];
    SolverVelocity& b = bodies.velocity[j.b];
    a.linear -= toLanes(impulse * bodies.inverseMass[j.a]);
    a.angular -= toLanes(bodies.inverseInertia[j.a] * glm::cross(j.ra, impulse));
    b.linear += toLanes(impulse * bodies.inverseMass[j.b]);
    b.angular += toLanes(bodies.inverseInertia[j.b] * glm::cross(j.rb, impulse));
}

void applyTurnImpulse(const Joint& j, glm::vec2 impulse, SolverBodies& bodies) {
    const glm::vec3 torque = j.turn[0] * impulse.x + j.turn[1] * impulse.y;
    bodies.velocity[j.a].angular += toLanes(bodies.inverseInertia[j.a] * torque);
    bodies.velocity[j.b].angular -= toLanes(bodies.inverseInertia[j.b] * torque);
}

} // namespace

void warmStartJoints(std::span<const Joint> joints, SolverBodies& bodies) {
    for (const Joint& j : joints) {
        if (!j.active) continue;
        applyPointImpulse(j, j.pointImpulse, bodies);
        if (j.type == JointType::Hinge) applyTurnImpulse(j, j.turnImpulse, bodies);
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
        applyTurnImpulse(j, impulse, bodies);
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
    applyPointImpulse(j, impulse, bodies);
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
