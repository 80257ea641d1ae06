// host/collision/contact.h: what the narrow phase hands the solver: body pairs and contact
// manifolds with feature ids for warm starting.
#pragma once

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace rubble {

/// Two bodies whose bounds overlap; a < b.
struct BodyPair {
    std::uint32_t a = 0, b = 0;
    friend bool operator==(const BodyPair&, const BodyPair&) = default;
    friend auto operator<=>(const BodyPair&, const BodyPair&) = default;
};

/// One contact point of a manifold.
struct ContactPoint {
    glm::vec3 position{0.0f}; ///< midway between the two surfaces, world, m
    float depth = 0.0f;       ///< penetration along the normal, m (negative: a gap)
    std::uint32_t feature = 0; ///< stays the same while the same features touch
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< the manifold's normal: unit, world, from a to b
};

/// The contact between two bodies: up to four points sharing one normal.
struct Manifold {
    std::uint32_t a = 0, b = 0;  ///< body indices, as in the pair
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< unit, world, pointing from a to b
    std::uint32_t count = 0;
    std::array<ContactPoint, 4> points{};
};

} // namespace rubble
