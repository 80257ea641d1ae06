// host/gpu/coloring.h: the batches of the device's Gauss-Seidel solve: the step's elements (a
// pair's contact rows, a joint's rows) colored greedily on the host so that no two elements of
// a color share a body that moves; each color is one launch of the sweep kernels
// (host/gpu/pgs.cpp). Why on the host, and what a GPU would change: docs/opencl.md.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace rubble::gpu {

/// An element as Coloring::addBySupport takes it: its id and bodies, and which of them move.
struct ColorElement {
    std::uint32_t id, a, b;
    bool movesA, movesB;
};

/// Greedy coloring: add() in the order elements are added (first fit, as Welsh and Powell's
/// sequential coloring without the degree sort: an element takes the lowest color that no earlier
/// element on one of its moving bodies has), addBySupport() in an order and with preferred colors
/// of its own. A body that does not move (static, asleep, kinematic) joins nothing: its velocity
/// is only read. The result depends on the input alone.
class Coloring {
  public:
    /// Starts a step's coloring over `bodies` bodies.
    void begin(std::uint32_t bodies);
    /// Colors element `id` acting on bodies a and b (each counted only when it moves).
    void add(std::uint32_t id, std::uint32_t a, std::uint32_t b, bool movesA, bool movesB);
    /// Colors contact elements from the bottom up (after any added one by one): each body's
    /// level is its distance in elements from a body that does not move; the elements go in
    /// order of their lower body's level (the given order within a level), and an element
    /// prefers the color after the one of the element its lower body rests on. A column of
    /// bodies then runs through the colors upward, so that one sweep of the colors in order
    /// carries a support up as many bodies as there are colors (first fit alternates two colors
    /// up a column: two bodies a sweep) (docs/opencl.md, "Coloring by support").
    void addBySupport(std::span<const ColorElement> elements);
    /// Sorts the elements by color (stably: in the order they were added within a color).
    void finish();

    /// The elements' ids, color by color.
    std::span<const std::uint32_t> order() const { return order_; }
    /// Color c is order()[start()[c] .. start()[c + 1]).
    std::span<const std::uint32_t> start() const { return start_; }
    std::uint32_t colors() const { return std::uint32_t(start_.empty() ? 0 : start_.size() - 1); }
    /// Where each element went in order(), in the order they were added.
    std::span<const std::uint32_t> slots() const { return slots_; }

  private:
    std::uint32_t freeColor(std::uint32_t a, std::uint32_t b, bool movesA, bool movesB,
                            std::uint32_t preferred);
    bool taken(std::uint32_t body, std::uint32_t color) const;
    // The first color from `preferred` on, in turn through the colors taken so far, that
    // neither moving body has, else the lowest free one above them; marked on both bodies.
    std::uint32_t take(std::uint32_t a, std::uint32_t b, bool movesA, bool movesB,
                       std::uint32_t preferred);
    void widen();

    std::uint32_t bodies_ = 0;
    std::uint32_t words_ = 1;         ///< 64-bit words of each body's mask
    std::vector<std::uint64_t> used_; ///< per body: the colors its elements took
    std::vector<std::uint32_t> ids_, colorOf_;
    std::vector<std::uint32_t> order_, start_, next_, slots_;
    std::uint32_t colors_ = 0; ///< colors taken so far
    // addBySupport's scratch: levels, adjacency, the order and each body's support color.
    std::vector<std::uint32_t> level_, adjacencyStart_, adjacency_, queue_, byLevel_, support_;
};

} // namespace rubble::gpu
