// tests/unit/transform.h: rigid transforms (rotation matrix and translation) in glm, as the tests
// pose hulls against each other (test::rigidOf in flat_hull.h hands them to the shared narrow
// phase as rubble/shared/hull.h's RigidTransform, which the stages use).
#pragma once

#include <glm/glm.hpp>


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

/// b's frame seen from a's frame: inverse(a) then b, that is x_a = R_a^T (R_b x_b + t_b - t_a).
inline Transform relative(const Transform& a, const Transform& b) {
    const glm::mat3 rt = glm::transpose(a.rotation);
    return Transform{rt * b.rotation, rt * (b.translation - a.translation)};
}

} // namespace rubble
