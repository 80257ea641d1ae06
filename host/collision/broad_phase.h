// host/collision/broad_phase.h: CPU stage broadPhase: overlapping axis-aligned boxes by sweep and
// prune in strips (boxes sorted along the axis of widest spread within slabs of a second axis),
// infinite planes against every box, pairs sorted.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "host/collision/contact.h"

namespace rubble {

/// An axis-aligned box, world frame, m.
struct Aabb {
    glm::vec3 min{0.0f}, max{0.0f};
};

/// Broad-phase flags of a body.
enum BroadPhaseFlag : std::uint8_t {
    kBroadPhaseInactive = 1, ///< static or asleep: never paired with another inactive body
    kBroadPhaseNoBox = 2,    ///< not swept (planes, which are paired through PlaneProxy)
};

/// A plane body: solid below dot(normal, x) = offset, world frame.
struct PlaneProxy {
    std::uint32_t body = 0;
    glm::vec3 normal{0.0f, 1.0f, 0.0f};
    float offset = 0.0f; ///< m
};

/// Arrays the broad phase reuses from step to step.
struct BroadPhaseScratch {
    struct Entry {
        float min, max;         ///< the box along the sweep axis
        std::uint32_t body;
        std::uint32_t strip;
    };
    std::vector<Entry> entries;
};

/// Every pair (a < b, sorted, each once) of bodies whose boxes overlap (touching counts), unless
/// both are inactive, plus every active body whose box reaches below a plane. `boxes` and
/// `flags` are indexed by body; boxes of kBroadPhaseNoBox bodies are ignored, as are non-finite
/// boxes. Sweep and prune in strips: bodies are binned into slabs of the second-widest axis
/// (at least two mean box widths, at most kMaxStrips of them), each slab sorted and swept along
/// the widest axis; a pair seen in two slabs is reported by the one holding the lower end of
/// the overlap. O(n log n + pairs) for bodies of similar size.
void findPairs(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
               std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs,
               BroadPhaseScratch& scratch);

/// The same by testing every pair: the reference for tests.
void findPairsBruteForce(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
                         std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs);

/// Most slabs the sweep uses.
inline constexpr std::uint32_t kMaxStrips = 4096;

} // namespace rubble
