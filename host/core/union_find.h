// host/core/union_find.h: disjoint sets over 0 .. n-1 by union-find with path halving. The
// smaller root wins every union, so each set's root is its smallest member whatever order the
// unions come in: islands, joint groups and merged faces come out the same on every run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace rubble {

class UnionFind {
public:
    UnionFind() = default;
    explicit UnionFind(std::size_t n) { reset(n); }

    /// n sets of one, reusing the storage.
    void reset(std::size_t n) {
        parent_.resize(n);
        for (std::size_t i = 0; i < n; ++i) parent_[i] = std::uint32_t(i);
    }

    /// The root (smallest member) of i's set.
    std::uint32_t find(std::uint32_t i) {
        while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
        return i;
    }

    /// Joins the sets of a and b; returns the root of the union.
    std::uint32_t unite(std::uint32_t a, std::uint32_t b) {
        std::uint32_t ra = find(a), rb = find(b);
        if (rb < ra) std::swap(ra, rb);
        parent_[rb] = ra;
        return ra;
    }

private:
    std::vector<std::uint32_t> parent_;
};

} // namespace rubble
