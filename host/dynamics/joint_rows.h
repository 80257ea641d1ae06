// host/dynamics/joint_rows.h: the rows of a ball or hinge joint at given poses, shared by the
// PGS joints (joints.cpp, rows once a step) and the soft step (soft_step.cpp, rows at each
// substep's poses): the point rows' matrix, the hinge's two angular rows and their matrix, and
// an impulse on both bodies.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "host/core/math.h"
#include "host/dynamics/joints.h"

namespace rubble {

/// The cross-product matrix: skew(r) v = r x v (glm is column-major).
inline glm::mat3 skew(glm::vec3 r) {
    return glm::mat3(glm::vec3(0.0f, r.z, -r.y), glm::vec3(-r.z, 0.0f, r.x),
                     glm::vec3(r.y, -r.x, 0.0f));
}

/// K of the point rows: (m_a^-1 + m_b^-1) 1 - [r_a] I_a^-1 [r_a] - [r_b] I_b^-1 [r_b].
inline glm::mat3 pointMatrix(glm::vec3 ra, glm::vec3 rb, float ima, float imb, const glm::mat3& ia,
                             const glm::mat3& ib) {
    const glm::mat3 sa = skew(ra), sb = skew(rb);
    return glm::mat3(ima + imb) - sa * ia * sa - sb * ib * sb;
}

/// Inverse of a symmetric positive (semi-)definite matrix; zero when singular.
inline glm::mat3 safeInverse(const glm::mat3& k) {
    const float det = glm::determinant(k);
    return std::abs(det) > 1e-12f ? glm::inverse(k) : glm::mat3(0.0f);
}
inline glm::mat2 safeInverse(const glm::mat2& k) {
    const float det = glm::determinant(k);
    return std::abs(det) > 1e-12f ? glm::inverse(k) : glm::mat2(0.0f);
}

/// The hinge rows' angular Jacobian on a: a_1 x b_2 and a_1 x c_2 at the given poses; the
/// constraint values a_1 . b_2, a_1 . c_2 go to c when it is not null.
inline void hingeRows(const Joint& j, const shared::BodyPose& pa, const shared::BodyPose& pb,
                      glm::vec3 turn[2], glm::vec2* c) {
    const glm::vec3 a1 = toVec3(shared::quatRotate(pa.orientation, toFloat4(j.axisA)));
    const glm::vec3 b2 = toVec3(shared::quatRotate(pb.orientation, toFloat4(j.perpB[0])));
    const glm::vec3 c2 = toVec3(shared::quatRotate(pb.orientation, toFloat4(j.perpB[1])));
    turn[0] = glm::cross(a1, b2);
    turn[1] = glm::cross(a1, c2);
    if (c) *c = glm::vec2(glm::dot(a1, b2), glm::dot(a1, c2));
}

/// K of the hinge's two angular rows.
inline glm::mat2 hingeMatrix(const glm::vec3 turn[2], const glm::mat3& ia, const glm::mat3& ib) {
    const glm::mat3 sum = ia + ib;
    const float k00 = glm::dot(turn[0], sum * turn[0]);
    const float k01 = glm::dot(turn[0], sum * turn[1]);
    const float k11 = glm::dot(turn[1], sum * turn[1]);
    return glm::mat2(k00, k01, k01, k11);
}

/// The point rows' impulse (on b; its opposite on a) at arms ra, rb into both velocities.
inline void applyPointImpulse(const Joint& j, glm::vec3 ra, glm::vec3 rb, glm::vec3 impulse,
                              SolverBodies& bodies) {
    SolverVelocity& a = bodies.velocity[j.a];
    SolverVelocity& b = bodies.velocity[j.b];
    a.linear -= toLanes(impulse * bodies.inverseMass[j.a]);
    a.angular -= toLanes(bodies.inverseInertia[j.a] * glm::cross(ra, impulse));
    b.linear += toLanes(impulse * bodies.inverseMass[j.b]);
    b.angular += toLanes(bodies.inverseInertia[j.b] * glm::cross(rb, impulse));
}

/// The hinge rows' impulse (on a; its opposite on b) into both angular velocities.
inline void applyTurnImpulse(const Joint& j, const glm::vec3 turn[2], glm::vec2 impulse,
                             SolverBodies& bodies) {
    const glm::vec3 torque = turn[0] * impulse.x + turn[1] * impulse.y;
    bodies.velocity[j.a].angular += toLanes(bodies.inverseInertia[j.a] * torque);
    bodies.velocity[j.b].angular -= toLanes(bodies.inverseInertia[j.b] * torque);
}

} // namespace rubble
