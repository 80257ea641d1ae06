// host/gpu/coloring.cpp: greedy first-fit coloring of the solve's elements (host/gpu/coloring.h).
#include "host/gpu/coloring.h"

#include <algorithm>
#include <bit>

namespace rubble::gpu {

void Coloring::begin(std::uint32_t bodies) {
    bodies_ = bodies;
    used_.assign(std::size_t(bodies) * words_, 0);
    ids_.clear();
    colorOf_.clear();
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

std::uint32_t Coloring::freeColor(std::uint32_t a, std::uint32_t b, bool movesA, bool movesB) {
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

void Coloring::add(std::uint32_t id, std::uint32_t a, std::uint32_t b, bool movesA, bool movesB) {
    const std::uint32_t c = freeColor(a, b, movesA, movesB);
    const std::uint64_t bit = std::uint64_t(1) << (c % 64);
    if (movesA) used_[std::size_t(a) * words_ + c / 64] |= bit;
    if (movesB) used_[std::size_t(b) * words_ + c / 64] |= bit;
    ids_.push_back(id);
    colorOf_.push_back(c);
}

void Coloring::finish() {
    std::uint32_t colors = 0;
    for (const std::uint32_t c : colorOf_) colors = std::max(colors, c + 1);
    // Counting sort by color.
    start_.assign(std::size_t(colors) + 1, 0);
    for (const std::uint32_t c : colorOf_) ++start_[c + 1];
    for (std::uint32_t c = 0; c < colors; ++c) start_[c + 1] += start_[c];
    order_.resize(ids_.size());
    next_.assign(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < ids_.size(); ++i) order_[next_[colorOf_[i]]++] = ids_[i];
}

} // namespace rubble::gpu
