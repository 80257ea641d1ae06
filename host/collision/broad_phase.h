// host/collision/broad_phase.h: CPU stage broadPhase: overlapping axis-aligned boxes by sweep and
// prune in columns (boxes sorted along the axis of widest spread within the cells of a grid over
// the other two axes), infinite planes against every box, pairs sorted.
#pragma once

#include <cstdint>
#include <limits>
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
    /// One body in one column, holding all of its box so that the sweep reads memory in order.
    struct Entry {
        std::uint32_t minBits; ///< sweep-axis minimum as bits whose unsigned order is numeric
        std::uint32_t maxBits; ///< sweep-axis maximum, the same way
        std::uint32_t body;    ///< body index; the top bit marks an inactive body
        float uMin, uMax;      ///< along the column grid's first axis
        float vMin, vMax;      ///< along its second axis
    };
    std::vector<Entry> entries;             ///< grouped by column
    std::vector<std::uint32_t> columnStart; ///< first entry of each column, and the end
    std::vector<std::uint32_t> columnCursor;
    /// The swept bodies as (sweep-axis minimum bits << 32 | body), sorted; kept from step to
    /// step so that sorting starts from last step's order.
    std::vector<std::uint64_t> keys;
    std::vector<std::uint32_t> pairStart; ///< first pair of each body, while sorting the pairs
    std::vector<BodyPair> pairBuffer;
    /// Most pairs findPairs may report (host/core/limits.h); past it, it stops, leaves `pairs`
    /// empty and sets `overflowed`.
    std::size_t pairLimit = std::numeric_limits<std::size_t>::max();
    bool overflowed = false;
};

/// Every pair (a < b, sorted, each once) of bodies whose boxes overlap (touching counts), unless
/// both are inactive, plus every active body whose box reaches below a plane. `boxes` and
/// `flags` are indexed by body; boxes of kBroadPhaseNoBox bodies are ignored, as are non-finite
/// boxes. Sweep and prune in columns (multi-box pruning): the two axes where the box centres
/// spread least are cut into a grid of columns (cells at least two mean box widths wide, at most
/// kMaxStrips a side, no more columns than twice the bodies); each column is sorted and swept
/// along the third axis, and a pair seen in two columns is reported by the one holding the
/// lower corner of the overlap. O(n log n + pairs) for bodies of similar size. Stops with no
/// pairs and scratch.overflowed set once more than scratch.pairLimit pairs are found.
void findPairs(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
               std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs,
               BroadPhaseScratch& scratch);

/// The same by testing every pair: the reference for tests.
void findPairsBruteForce(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
                         std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs);

/// Most cells along each axis of the column grid.
inline constexpr std::uint32_t kMaxStrips = 4096;

} // namespace rubble
