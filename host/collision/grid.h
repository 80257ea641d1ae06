// host/collision/grid.h: OpenCL stage buildGrid on the CPU, twin of kernels/grid.cl (dispatch in
// host/gpu/grid.cpp): cell keys of the particles, sorted, and each cell's range of sorted slots.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rubble/shared/particle.h"

namespace rubble {

/// The uniform grid over the particles, rewritten every step.
struct ParticleGrid {
    std::vector<std::uint32_t> keys;               ///< cell keys, sorted
    std::vector<std::uint32_t> order;              ///< particle of each sorted slot
    std::vector<std::uint32_t> cellStart, cellEnd; ///< sorted slots of each cell, or empty
};

/// Grid hash table size for a particle count: 2^bits >= 2 count, 2^10 .. 2^24.
std::uint32_t gridBits(std::size_t particleCount);

/// Stage buildGrid: cell keys, a stable sort of the particles by key (the device's LSD radix
/// sort gives the same order), each cell's range of sorted slots.
/// reads: world   writes: grid
void buildGrid(std::span<const shared::float4> world, float cellSize, std::uint32_t bits,
               ParticleGrid& grid);

} // namespace rubble
