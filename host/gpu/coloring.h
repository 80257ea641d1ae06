// host/gpu/coloring.h: the batches of the device's Gauss-Seidel solve: the step's elements (a
// pair's contact rows, a joint's rows) colored greedily on the host so that no two elements of
// a color share a body that moves; each color is one launch of the sweep kernels
// (host/gpu/pgs.cpp). Why on the host, and what a GPU would change: docs/opencl.md.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace rubble::gpu {

/// Greedy coloring in the order elements are added (first fit, as Welsh and Powell's sequential
/// coloring without the degree sort): an element takes the lowest color that no earlier element
/// on one of its moving bodies has. A body that does not move (static, asleep, kinematic) joins
/// nothing: its velocity is only read. The result depends on the order alone.
class Coloring {
  public:
    /// Starts a step's coloring over `bodies` bodies.
    void begin(std::uint32_t bodies);
    /// Colors element `id` acting on bodies a and b (each counted only when it moves).
    void add(std::uint32_t id, std::uint32_t a, std::uint32_t b, bool movesA, bool movesB);
    /// Sorts the elements by color (stably: in the order they were added within a color).
    void finish();

    /// The elements' ids, color by color.
    std::span<const std::uint32_t> order() const { return order_; }
    /// Color c is order()[start()[c] .. start()[c + 1]).
    std::span<const std::uint32_t> start() const { return start_; }
    std::uint32_t colors() const { return std::uint32_t(start_.empty() ? 0 : start_.size() - 1); }

  private:
    std::uint32_t freeColor(std::uint32_t a, std::uint32_t b, bool movesA, bool movesB);
    void widen();

    std::uint32_t bodies_ = 0;
    std::uint32_t words_ = 1;         ///< 64-bit words of each body's mask
    std::vector<std::uint64_t> used_; ///< per body: the colors its elements took
    std::vector<std::uint32_t> ids_, colorOf_;
    std::vector<std::uint32_t> order_, start_, next_;
};

} // namespace rubble::gpu
