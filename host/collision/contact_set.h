// host/collision/contact_set.h: the contacts of one pair in one shape's frame, as the narrow-phase
// functions return them, and the packing of feature ids. host/collision/narrow_phase.cpp turns a
// ContactSet into a world Manifold.
#pragma once

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace rubble {

/// A manifold never holds more points than this.
inline constexpr std::uint32_t kMaxContactPoints = 4;

/// Contacts are made while the shapes are closer than this (m), so that a resting body keeps
/// its contacts through small bounces; their depth is then negative (a gap).
inline constexpr float kContactMargin = 0.004f;

/// One contact point in the frame of its ContactSet.
struct LocalContact {
    glm::vec3 position{0.0f};  ///< midway between the two surfaces, m
    float depth = 0.0f;        ///< penetration along the normal, m (negative: a gap)
    std::uint32_t feature = 0; ///< see makeFeatureId
};

/// Up to four contacts sharing one normal, pointing from the first shape to the second.
struct ContactSet {
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< unit
    std::uint32_t count = 0;
    std::array<LocalContact, kMaxContactPoints> points{};

    void add(glm::vec3 position, float depth, std::uint32_t feature) {
        if (count < kMaxContactPoints) points[count++] = LocalContact{position, depth, feature};
    }
};

/// What kind of feature pair made a contact point: the top two bits of its feature id.
enum class ContactKind : std::uint32_t {
    FaceA = 0,     ///< a face of the first shape clipped the other's incident face
    FaceB = 1,     ///< the same with the roles swapped
    Edges = 2,     ///< closest points of an edge of each
    Primitive = 3, ///< a sphere or plane contact, or a hull vertex against a plane
};

/// Feature ids: 2 bits of kind, then two 15-bit fields whose meaning the kind gives (clip plane
/// and incident segment, edge and edge, vertex). Indices past 15 bits wrap, which can only
/// alias ids on hulls with more than 16k half-edges.
inline std::uint32_t makeFeatureId(ContactKind kind, std::uint32_t high, std::uint32_t low) {
    return (std::uint32_t(kind) << 30) | ((high & 0x7FFFu) << 15) | (low & 0x7FFFu);
}

} // namespace rubble
