// host/collision/clip.h: the geometric steps of manifold building, part of CPU stage narrowPhase:
// Sutherland-Hodgman clipping with feature tags, reduction to four points, closest points of two
// segments (Gregorius, "Robust Contact Creation for Physics Simulations", GDC 2015; Ericson,
// "Real-Time Collision Detection", 5.1.9; physics report 3.4.1).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "host/collision/contact_set.h"

namespace rubble {

/// A segment tag with this bit runs along the clip line of the reference half-edge in the low
/// bits; without it, along the incident half-edge it names.
inline constexpr std::uint32_t kClipLineTag = 0x4000u;

/// A vertex of the polygon being clipped. Trivial on purpose: clipping buffers live on the stack
/// and are filled before they are read.
struct ClipVertex {
    glm::vec3 position;
    std::uint32_t clipEdge; ///< reference half-edge + 1 whose plane made it; 0: an original
    std::uint32_t tag;      ///< the incident segment it sits on (see segment)
    std::uint32_t segment;  ///< tag of the segment that starts here
};

/// One Sutherland-Hodgman pass: the part of the closed polygon `in` where
/// dot(normal, x) <= offset. A crossing point gets `clipEdge` (the reference half-edge) and the
/// tag of the segment it cuts, so that its id stays the same while the same features cross;
/// leaving the half-space, the next segment runs along the clip line. `out` needs room for
/// in.size() + 1 vertices; returns how many were written.
std::size_t clipPolygon(std::span<const ClipVertex> in, glm::vec3 normal, float offset,
                        std::uint32_t clipEdge, std::span<ClipVertex> out);

/// Picks at most four of `points` (Gregorius 2015): the deepest, the one furthest from it, the
/// one spanning the largest triangle with those two (areas measured about `normal`), and the one
/// adding the most area on the far side. Writes their indices to `keep`; returns how many.
std::uint32_t reduceContacts(std::span<const LocalContact> points, glm::vec3 normal,
                             std::array<std::uint32_t, kMaxContactPoints>& keep);

/// The closest points c1 on segment p1-q1 and c2 on segment p2-q2 (Ericson 5.1.9).
void closestPointsOnSegments(glm::vec3 p1, glm::vec3 q1, glm::vec3 p2, glm::vec3 q2, glm::vec3& c1,
                             glm::vec3& c2);

} // namespace rubble
