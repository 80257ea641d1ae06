// host/collision/broad_phase.cpp: CPU stage broadPhase: sweep and prune in columns, planes by a
// box's lowest corner, pairs sorted (Ericson, "Real-Time Collision Detection", 7.5).
#include "host/collision/broad_phase.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "host/core/math.h"

namespace rubble {
namespace {

// A column is at least this many mean box widths wide, so that most boxes sit in one to four.
constexpr float kStripWidthFactor = 2.0f;

// A row of equal cells along one axis: at least kStripWidthFactor mean box widths wide, at
// most kMaxStrips of them.
struct Strips {
    float origin = 0.0f, width = 1.0f;
    std::uint32_t count = 1;
    std::uint32_t of(float x) const {
        // Clamped at 0 first, truncation is the floor.
        return std::uint32_t(std::clamp((x - origin) / width, 0.0f, float(count - 1)));
    }
};

Strips makeStrips(float lo, float hi, float cellWidth) {
    Strips s;
    s.origin = lo;
    s.width = std::max(cellWidth, (hi - lo) / float(kMaxStrips));
    if (!(s.width > 0.0f)) s.width = 1.0f;
    s.count =
        std::uint32_t(std::clamp(std::floor((hi - lo) / s.width) + 1.0f, 1.0f, float(kMaxStrips)));
    return s;
}

// Sorts keys that often arrive nearly in order (bodies generated row by row, or in last step's
// order): insertion sort while it moves few keys, std::sort once it has moved too many. The
// keys are distinct, so either way gives the same order.
void sortNearlySorted(std::vector<std::uint64_t>& keys) {
    const std::size_t n = keys.size();
    std::size_t budget = 8 * n;
    for (std::size_t i = 1; i < n; ++i) {
        const std::uint64_t key = keys[i];
        std::size_t j = i;
        for (; j > 0 && keys[j - 1] > key; --j) keys[j] = keys[j - 1];
        keys[j] = key;
        if (i - j > budget) {
            std::sort(keys.begin(), keys.end());
            return;
        }
        budget -= i - j;
    }
}

// Marks an inactive body in a sweep entry's body index.
constexpr std::uint32_t kInactiveBit = 0x80000000u;

// The bits of a float rearranged so that unsigned order is numeric order.
std::uint32_t orderedBits(float x) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
    return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}

bool overlaps(const Aabb& a, const Aabb& b) {
    return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
           a.min.z <= b.max.z && b.min.z <= a.max.z;
}

// The box's lowest point along n is below the plane's surface.
bool reachesPlane(const Aabb& box, const PlaneProxy& p) {
    const glm::vec3 centre = (box.min + box.max) * 0.5f, half = (box.max - box.min) * 0.5f;
    return glm::dot(p.normal, centre) - glm::dot(glm::abs(p.normal), half) <= p.offset;
}

bool swept(const Aabb& box, std::uint8_t flags) {
    return !(flags & kBroadPhaseNoBox) && isFinite(box.min) && isFinite(box.max);
}

BodyPair ordered(std::uint32_t i, std::uint32_t j) {
    return i < j ? BodyPair{i, j} : BodyPair{j, i};
}

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

// Sorts pairs (a < b) of bodies below `bodies` in O(n + bodies): a counting sort on a, then
// an insertion sort of each body's few partners; duplicates removed.
void sortPairsByBody(std::vector<BodyPair>& pairs, std::uint32_t bodies,
                     BroadPhaseScratch& scratch) {
    auto& start = scratch.pairStart;
    start.assign(bodies + 1, 0);
    for (const BodyPair& p : pairs) ++start[p.a + 1];
    for (std::uint32_t i = 0; i < bodies; ++i) start[i + 1] += start[i];
    auto& sorted = scratch.pairBuffer;
    sorted.resize(pairs.size());
    auto& cursor = scratch.columnCursor;
    cursor.assign(start.begin(), start.end() - 1);
    for (const BodyPair& p : pairs) sorted[cursor[p.a]++] = p;
    for (std::uint32_t a = 0; a < bodies; ++a)
        for (std::uint32_t i = start[a] + 1; i < start[a + 1]; ++i) {
            const BodyPair p = sorted[i];
            std::uint32_t j = i;
            for (; j > start[a] && sorted[j - 1].b > p.b; --j) sorted[j] = sorted[j - 1];
            sorted[j] = p;
        }
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    pairs.swap(sorted);
}

} // namespace

void findPairs(std::span<const Aabb> boxes, std::span<const std::uint8_t> flags,
               std::span<const PlaneProxy> planes, std::vector<BodyPair>& pairs,
               BroadPhaseScratch& scratch) {
    pairs.clear();
    scratch.overflowed = false;
    const auto n = std::uint32_t(boxes.size());

    // The sweep runs along the axis where the centres spread most; columns cut the other two.
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
        const glm::dvec3 mean = sum / double(count);
        const glm::dvec3 variance = sum2 / double(count) - mean * mean;
        int order[3] = {0, 1, 2};
        std::sort(order, order + 3, [&](int x, int y) {
            return variance[x] > variance[y] || (variance[x] == variance[y] && x < y);
        });
        const int axis = order[0], u = order[1], v = order[2];
        // Columns of kStripWidthFactor mean widths, widened if there would be more columns
        // than bodies (the column table is counted every step).
        float widthU = kStripWidthFactor * float(width[u] / double(count));
        float widthV = kStripWidthFactor * float(width[v] / double(count));
        Strips su = makeStrips(lo[u], hi[u], widthU), sv = makeStrips(lo[v], hi[v], widthV);
        const double columnLimit = std::max(1024.0, 2.0 * double(count));
        if (double(su.count) * double(sv.count) > columnLimit) {
            const float grow =
                float(std::sqrt(double(su.count) * double(sv.count) / columnLimit)) * 1.01f;
            su = makeStrips(lo[u], hi[u], su.width * grow);
            sv = makeStrips(lo[v], hi[v], sv.width * grow);
        }
        auto cellOf = [&](float x, float y) { return su.of(x) * sv.count + sv.of(y); };

        // The swept bodies in order along the sweep axis (minimum, then index). Last step's
        // order is the starting point, so that an insertion sort usually finishes in O(n).
        auto& keys = scratch.keys;
        auto keyOf = [&](std::uint32_t body) {
            return (std::uint64_t(orderedBits(boxes[body].min[axis])) << 32) | body;
        };
        bool reuse = keys.size() == count;
        for (std::size_t k = 0; reuse && k < keys.size(); ++k) {
            const auto body = std::uint32_t(keys[k]);
            if (body < n && swept(boxes[body], flags[body]))
                keys[k] = keyOf(body);
            else
                reuse = false; // the set of swept bodies changed
        }
        if (!reuse) {
            keys.clear();
            for (std::uint32_t i = 0; i < n; ++i)
                if (swept(boxes[i], flags[i])) keys.push_back(keyOf(i));
        }
        sortNearlySorted(keys);

        // One entry per body and column it touches, placed by a counting sort on the column
        // that keeps the sweep order; each holds the whole box so that the sweep reads memory
        // in order.
        const std::uint32_t columns = su.count * sv.count;
        auto& start = scratch.columnStart;
        start.assign(columns + 1, 0);
        for (std::uint32_t i = 0; i < n; ++i) {
            if (!swept(boxes[i], flags[i])) continue;
            const Aabb& b = boxes[i];
            const std::uint32_t u0 = su.of(b.min[u]), u1 = su.of(b.max[u]);
            const std::uint32_t v0 = sv.of(b.min[v]), v1 = sv.of(b.max[v]);
            for (std::uint32_t cu = u0; cu <= u1; ++cu)
                for (std::uint32_t cv = v0; cv <= v1; ++cv) ++start[cu * sv.count + cv + 1];
        }
        for (std::uint32_t c = 0; c < columns; ++c) start[c + 1] += start[c];
        auto& entries = scratch.entries;
        entries.resize(start[columns]);
        auto& cursor = scratch.columnCursor;
        cursor.assign(start.begin(), start.end() - 1);
        for (const std::uint64_t key : keys) {
            const auto i = std::uint32_t(key);
            const Aabb& b = boxes[i];
            const std::uint32_t body = i | ((flags[i] & kBroadPhaseInactive) ? kInactiveBit : 0u);
            const std::uint32_t u0 = su.of(b.min[u]), u1 = su.of(b.max[u]);
            const std::uint32_t v0 = sv.of(b.min[v]), v1 = sv.of(b.max[v]);
            for (std::uint32_t cu = u0; cu <= u1; ++cu)
                for (std::uint32_t cv = v0; cv <= v1; ++cv) {
                    const std::uint32_t cell = cu * sv.count + cv;
                    entries[cursor[cell]++] = {orderedBits(b.min[axis]),
                                               orderedBits(b.max[axis]),
                                               body,
                                               b.min[u],
                                               b.max[u],
                                               b.min[v],
                                               b.max[v]};
                }
        }

        // Sweep each column: later entries start after this one does; stop past its end.
        for (std::uint32_t cell = 0; cell < columns; ++cell) {
            const auto first = entries.begin() + start[cell];
            const auto last = entries.begin() + start[cell + 1];
            for (auto e = first; e != last; ++e) {
                for (auto f = e + 1; f != last && f->minBits <= e->maxBits; ++f) {
                    // One branch, mostly not taken: both inactive, or apart across the column.
                    const bool apart = ((e->body & f->body & kInactiveBit) != 0) |
                                       (f->uMin > e->uMax) | (e->uMin > f->uMax) |
                                       (f->vMin > e->vMax) | (e->vMin > f->vMax);
                    if (apart) continue;
                    // Report in the column of the overlap's lower corner only.
                    if (cellOf(std::max(e->uMin, f->uMin), std::max(e->vMin, f->vMin)) != cell)
                        continue;
                    pairs.push_back(ordered(e->body & ~kInactiveBit, f->body & ~kInactiveBit));
                    if (pairs.size() > scratch.pairLimit) {
                        // Bodies piled into each other: stop before the pairs fill memory.
                        scratch.overflowed = true;
                        pairs.clear();
                        return;
                    }
                }
            }
        }
    }
    addPlanePairs(boxes, flags, planes, pairs);
    sortPairsByBody(pairs, n, scratch);
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
