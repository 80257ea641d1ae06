// host/collision/grid.cpp: OpenCL stage buildGrid on the CPU; twin of kernels/grid.cl.
#include "host/collision/grid.h"

namespace rubble {

using namespace shared;

std::uint32_t gridBits(std::size_t particleCount) {
    std::uint32_t bits = 10;
    while (bits < 24 && (std::size_t(1) << bits) < 2 * particleCount) ++bits;
    return bits;
}

void buildGrid(std::span<const float4> world, float cellSize, std::uint32_t bits,
               ParticleGrid& grid) {
    const std::size_t n = world.size(), cells = std::size_t(1) << bits;
    const float inverse = 1.0f / cellSize;
    std::vector<std::uint32_t> unsorted(n);
    for (std::size_t i = 0; i < n; ++i) unsorted[i] = cellKeyItem(world[i], inverse, bits);
    // A stable counting sort by key.
    grid.cellStart.assign(cells, RUBBLE_EMPTY_CELL);
    grid.cellEnd.assign(cells, RUBBLE_EMPTY_CELL);
    std::vector<std::uint32_t> count(cells + 1, 0);
    for (std::uint32_t k : unsorted) ++count[k + 1];
    for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
    grid.keys.resize(n);
    grid.order.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t slot = count[unsorted[i]]++;
        grid.keys[slot] = unsorted[i];
        grid.order[slot] = std::uint32_t(i);
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::vector<std::uint32_t>& keys = grid.keys;
        if (i == 0 || keys[i] != keys[i - 1]) grid.cellStart[keys[i]] = std::uint32_t(i);
        if (i + 1 == n || keys[i] != keys[i + 1]) grid.cellEnd[keys[i]] = std::uint32_t(i + 1);
    }
}

} // namespace rubble
