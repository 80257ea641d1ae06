// host/collision/transform.h: rigid transforms (rotation matrix and translation) in glm, for the
// broad phase's boxes and planes, made from a body's BodyPose (the narrow phase uses
// rubble/shared/hull.h's RigidTransform).
#pragma once

#include <glm/glm.hpp>

#include "host/core/math.h"
#include "rubble/shared/body.h"

namespace rubble {

/// x' = rotation x + translation: a frame's pose in another frame.
struct Transform {
    glm::mat3 rotation{1.0f};
    glm::vec3 translation{0.0f}; ///< m

    glm::vec3 apply(glm::vec3 p) const { return rotation * p + translation; }
    glm::vec3 rotate(glm::vec3 v) const { return rotation * v; }
    /// The inverse rotation of v: R^T v.
    glm::vec3 rotateInverse(glm::vec3 v) const { return v * rotation; }
    glm::vec3 applyInverse(glm::vec3 p) const { return (p - translation) * rotation; }
};

/// The body-to-world transform of a pose.
inline Transform transformOf(const shared::BodyPose& pose) {
    return Transform{toMat3(shared::mat3FromQuat(pose.orientation)), toVec3(pose.position)};
}

/// The inverse transform.
inline Transform inverse(const Transform& t) {
    const glm::mat3 rt = glm::transpose(t.rotation);
    return Transform{rt, -(rt * t.translation)};
}

/// b's frame seen from a's frame: inverse(a) then b, that is x_a = R_a^T (R_b x_b + t_b - t_a).
inline Transform relative(const Transform& a, const Transform& b) {
    const glm::mat3 rt = glm::transpose(a.rotation);
    return Transform{rt * b.rotation, rt * (b.translation - a.translation)};
}

} // namespace rubble
