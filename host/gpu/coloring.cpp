// host/gpu/coloring.cpp: greedy coloring of the solve's elements, first fit or by support
// (host/gpu/coloring.h).
#include "host/gpu/coloring.h"

#include <algorithm>
#include <bit>

namespace rubble::gpu {

namespace {
constexpr std::uint32_t kNoLevel = 0xffffffffu;
constexpr std::uint32_t kNoColor = 0xffffffffu;
} // namespace

void Coloring::begin(std::uint32_t bodies) {
    bodies_ = bodies;
    used_.assign(std::size_t(bodies) * words_, 0);
    ids_.clear();
    colorOf_.clear();
    colors_ = 0;
}

bool Coloring::taken(std::uint32_t body, std::uint32_t color) const {
    return (used_[std::size_t(body) * words_ + color / 64] >> (color % 64)) & 1u;
}

void Coloring::widen() {
    // Twice the words per body, each body's colors kept.
    std::vector<std::uint64_t> wider(std::size_t(bodies_) * words_ * 2, 0);
    for (std::size_t i = 0; i < bodies_; ++i)
        std::copy_n(used_.begin() + std::ptrdiff_t(i * words_), words_,
                    wider.begin() + std::ptrdiff_t(i * words_ * 2));
    used_ = std::move(wider);
    words_ *= 2;
}

std::uint32_t Coloring::freeColor(std::uint32_t a, std::uint32_t b, bool movesA, bool movesB,
                                  std::uint32_t preferred) {
    // From the preferred color through the colors taken so far, in turn.
    for (std::uint32_t k = 0; preferred > 0 && k < colors_; ++k) {
        const std::uint32_t c = (preferred + k) % colors_;
        if (!(movesA && taken(a, c)) && !(movesB && taken(b, c))) return c;
    }
    for (;;) {
        for (std::uint32_t w = 0; w < words_; ++w) {
            std::uint64_t taken = 0;
            if (movesA) taken |= used_[std::size_t(a) * words_ + w];
            if (movesB) taken |= used_[std::size_t(b) * words_ + w];
            if (taken != ~std::uint64_t(0)) return w * 64 + std::uint32_t(std::countr_one(taken));
        }
        widen();
    }
}

std::uint32_t Coloring::take(std::uint32_t a, std::uint32_t b, bool movesA, bool movesB,
                             std::uint32_t preferred) {
    const std::uint32_t c = freeColor(a, b, movesA, movesB, preferred);
    const std::uint64_t bit = std::uint64_t(1) << (c % 64);
    if (movesA) used_[std::size_t(a) * words_ + c / 64] |= bit;
    if (movesB) used_[std::size_t(b) * words_ + c / 64] |= bit;
    colors_ = std::max(colors_, c + 1);
    return c;
}

void Coloring::add(std::uint32_t id, std::uint32_t a, std::uint32_t b, bool movesA, bool movesB) {
    ids_.push_back(id);
    colorOf_.push_back(take(a, b, movesA, movesB, 0));
}

void Coloring::addBySupport(std::span<const ColorElement> elements) {
    const std::size_t n = elements.size();
    // Each body's level, breadth first from the elements with one body that does not move (a
    // body that does not move is level 0; one never reached keeps kNoLevel).
    level_.assign(bodies_, kNoLevel);
    adjacencyStart_.assign(std::size_t(bodies_) + 1, 0);
    for (const ColorElement& x : elements)
        if (x.movesA && x.movesB) {
            ++adjacencyStart_[x.a + 1];
            ++adjacencyStart_[x.b + 1];
        }
    for (std::uint32_t i = 0; i < bodies_; ++i) adjacencyStart_[i + 1] += adjacencyStart_[i];
    adjacency_.resize(adjacencyStart_[bodies_]);
    next_.assign(adjacencyStart_.begin(), adjacencyStart_.end() - 1);
    for (const ColorElement& x : elements)
        if (x.movesA && x.movesB) {
            adjacency_[next_[x.a]++] = x.b;
            adjacency_[next_[x.b]++] = x.a;
        }
    queue_.clear();
    for (const ColorElement& x : elements) {
        if (x.movesA == x.movesB) continue;
        const std::uint32_t moving = x.movesA ? x.a : x.b;
        if (level_[moving] != kNoLevel) continue;
        level_[moving] = 1;
        queue_.push_back(moving);
    }
    for (std::size_t head = 0; head < queue_.size(); ++head) {
        const std::uint32_t i = queue_[head];
        for (std::uint32_t k = adjacencyStart_[i]; k < adjacencyStart_[i + 1]; ++k) {
            if (level_[adjacency_[k]] != kNoLevel) continue;
            level_[adjacency_[k]] = level_[i] + 1;
            queue_.push_back(adjacency_[k]);
        }
    }
    auto levelA = [&](const ColorElement& x) { return x.movesA ? level_[x.a] : 0u; };
    auto levelB = [&](const ColorElement& x) { return x.movesB ? level_[x.b] : 0u; };
    // The elements by their lower body's level, stably (a counting sort); those that no
    // support reaches (kNoLevel) last.
    std::uint32_t top = 0;
    for (const ColorElement& x : elements) {
        const std::uint32_t l = std::min(levelA(x), levelB(x));
        if (l != kNoLevel) top = std::max(top, l);
    }
    auto slot = [&](const ColorElement& x) {
        const std::uint32_t l = std::min(levelA(x), levelB(x));
        return l == kNoLevel ? top + 1 : l;
    };
    std::vector<std::uint32_t>& count = adjacencyStart_;
    count.assign(std::size_t(top) + 3, 0);
    for (const ColorElement& x : elements) ++count[slot(x) + 1];
    for (std::uint32_t l = 0; l <= top + 1; ++l) count[l + 1] += count[l];
    byLevel_.resize(n);
    for (std::size_t e = 0; e < n; ++e) byLevel_[count[slot(elements[e])]++] = std::uint32_t(e);
    // Colored in that order, each element preferring the color after the one its lower body
    // rests on; kept in the given order, so that a color's elements stay in it (pair order:
    // nearby bodies together in memory).
    support_.assign(bodies_, kNoColor);
    const std::size_t first = colorOf_.size();
    for (const ColorElement& x : elements) ids_.push_back(x.id);
    colorOf_.resize(first + n);
    for (const std::uint32_t e : byLevel_) {
        const ColorElement& x = elements[e];
        const std::uint32_t la = levelA(x), lb = levelB(x);
        const bool aLower = la <= lb;
        const std::uint32_t lower = aLower ? x.a : x.b, upper = aLower ? x.b : x.a;
        const bool lowerMoves = aLower ? x.movesA : x.movesB;
        const bool upperMoves = aLower ? x.movesB : x.movesA;
        const std::uint32_t below = lowerMoves ? support_[lower] : kNoColor;
        const std::uint32_t c =
            take(x.a, x.b, x.movesA, x.movesB, below == kNoColor ? 0 : below + 1);
        colorOf_[first + e] = c;
        // The first element found between a body and the level below carries its support.
        // (Breadth-first levels of an element's two ends differ by at most one.)
        if (upperMoves && la != lb && support_[upper] == kNoColor)
            support_[upper] = c;
    }
}

void Coloring::finish() {
    const std::uint32_t colors = colors_;
    // Counting sort by color.
    start_.assign(std::size_t(colors) + 1, 0);
    for (const std::uint32_t c : colorOf_) ++start_[c + 1];
    for (std::uint32_t c = 0; c < colors; ++c) start_[c + 1] += start_[c];
    order_.resize(ids_.size());
    next_.assign(start_.begin(), start_.end() - 1);
    slots_.resize(ids_.size());
    for (std::size_t i = 0; i < ids_.size(); ++i) {
        slots_[i] = next_[colorOf_[i]]++;
        order_[slots_[i]] = ids_[i];
    }
}

} // namespace rubble::gpu
