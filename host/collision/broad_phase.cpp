// host/collision/broad_phase.cpp: CPU stage broadPhase: sweep and prune in strips, planes by a
// box's lowest corner, pairs sorted (Ericson, "Real-Time Collision Detection", 7.5).
#include "host/collision/broad_phase.h"

#include <algorithm>
#include <cmath>

#include "host/core/math.h"

namespace rubble {
namespace {

// A slab is at least this many mean box widths wide, so that most boxes sit in one or two.
constexpr float kStripWidthFactor = 2.0f;

bool overlaps(const Aabb& a, const Aabb& b) {
    return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y &&
           b.min.y <= a.max.y && a.min.z <= b.max.z && b.min.z <= a.max.z;
}

// The box's lowest point along n is below the plane's surface.
bool reachesPlane(const Aabb& box, const PlaneProxy& p) {
    const glm::vec3 centre = (box.min + box.max) * 0.5f, half = (box.max - box.min) * 0.5f;
    return glm::dot(p.normal, centre) - glm::dot(glm::abs(p.normal), half) <= p.offset;
}

bool swept(const Aabb& box, std::uint8_t flags) {
    return !(flags & kBroadPhaseNoBox) && isFinite(box.min) && isFinite(box.max);
}

BodyPair ordered(std::uint32_t i, std::uint32_t j) { return i < j ? BodyPair{i, j} : BodyPair{j, i}; }

void addPlanePairs(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
                   std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs) {
    for (const PlaneProxy& p : planes)
        for (std::uint32_t i = 0; i < boxes.size(); ++i)
            if (!(flags[i] & kBroadPhaseInactive) && swept(boxes[i], flags[i]) &&
                reachesPlane(boxes[i], p) && i != p.body)
                pairs.push_back(ordered(p.body, i));
}

void sortUnique(std::vector<BodyPair>& pairs) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

} // namespace

void findPairs(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
               std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs,
               BroadPhaseScratch& scratch) {
    pairs.clear();
    const auto n = std::uint32_t(boxes.size());

    // The sweep runs along the axis where the centres spread most; slabs cut the second one.
    glm::dvec3 sum(0.0), sum2(0.0), width(0.0);
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    std::uint32_t count = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!swept(boxes[i], flags[i])) continue;
        const glm::dvec3 c = glm::dvec3(boxes[i].min + boxes[i].max) * 0.5;
        sum += c;
        sum2 += c * c;
        width += glm::dvec3(boxes[i].max - boxes[i].min);
        lo = glm::min(lo, boxes[i].min);
        hi = glm::max(hi, boxes[i].max);
        ++count;
    }
    if (count > 1) {
        const glm::dvec3 variance = sum2 / double(count) - (sum / double(count)) * (sum / double(count));
        int order[3] = {0, 1, 2};
        std::sort(order, order + 3, [&](int x, int y) {
            return variance[x] > variance[y] || (variance[x] == variance[y] && x < y);
        });
        const int axis = order[0], cut = order[1];
        float stripWidth = std::max(kStripWidthFactor * float(width[cut] / double(count)),
                                    (hi[cut] - lo[cut]) / float(kMaxStrips));
        if (!(stripWidth > 0.0f)) stripWidth = 1.0f;
        const float origin = lo[cut];
        auto stripOf = [&](float x) {
            const float s = std::floor((x - origin) / stripWidth);
            return std::uint32_t(std::clamp(s, 0.0f, float(kMaxStrips - 1)));
        };

        // One entry per body and slab it touches, sorted by slab, then along the sweep axis.
        auto& entries = scratch.entries;
        entries.clear();
        for (std::uint32_t i = 0; i < n; ++i) {
            if (!swept(boxes[i], flags[i])) continue;
            const std::uint32_t first = stripOf(boxes[i].min[cut]), last = stripOf(boxes[i].max[cut]);
            for (std::uint32_t s = first; s <= last; ++s)
                entries.push_back({boxes[i].min[axis], boxes[i].max[axis], i, s});
        }
        std::sort(entries.begin(), entries.end(), [](const auto& x, const auto& y) {
            if (x.strip != y.strip) return x.strip < y.strip;
            if (x.min != y.min) return x.min < y.min;
            return x.body < y.body;
        });

        // Sweep each slab: later entries start after this one does; stop past its end.
        for (std::size_t i = 0; i < entries.size(); ++i) {
            const auto& e = entries[i];
            const Aabb& box = boxes[e.body];
            const bool inactive = flags[e.body] & kBroadPhaseInactive;
            for (std::size_t j = i + 1; j < entries.size(); ++j) {
                const auto& f = entries[j];
                if (f.strip != e.strip || f.min > e.max) break;
                if (inactive && (flags[f.body] & kBroadPhaseInactive)) continue;
                const Aabb& other = boxes[f.body];
                if (!overlaps(box, other)) continue;
                // Report in the slab of the overlap's lower end only.
                if (stripOf(std::max(box.min[cut], other.min[cut])) != e.strip) continue;
                pairs.push_back(ordered(e.body, f.body));
            }
        }
    }
    addPlanePairs(boxes, flags, planes, pairs);
    sortUnique(pairs);
}

void findPairsBruteForce(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
                         std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs) {
    pairs.clear();
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
        for (std::uint32_t j = i + 1; j < boxes.size(); ++j) {
            if (!swept(boxes[i], flags[i]) || !swept(boxes[j], flags[j])) continue;
            if ((flags[i] & kBroadPhaseInactive) && (flags[j] & kBroadPhaseInactive)) continue;
            if (overlaps(boxes[i], boxes[j])) pairs.push_back({i, j});
        }
    addPlanePairs(boxes, flags, planes, pairs);
    sortUnique(pairs);
}

} // namespace rubble
