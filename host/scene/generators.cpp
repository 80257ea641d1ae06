// host/scene/generators.cpp: the grid generator's positions and seeded rotation jitter.
#include <numbers>
#include "host/scene/generators.h"

#include <cmath>
#include <random>

namespace rubble {

std::vector<glm::quat> jitterRotations(std::uint32_t seed, std::size_t count, float jitter) {
    std::mt19937 rng(seed);
    auto unit = [&rng] { return double(rng() >> 8) / double(1u << 24); };
    std::vector<glm::quat> out;
    out.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const double z = 2.0 * unit() - 1.0;
        const double phi = 2.0 * std::numbers::pi * unit();
        const double angle = (2.0 * unit() - 1.0) * double(jitter);
        const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
        const glm::dvec3 axis(s * std::cos(phi), s * std::sin(phi), z);
        const glm::dquat q = glm::angleAxis(angle, glm::normalize(axis));
        out.push_back(glm::normalize(glm::quat(q)));
    }
    return out;
}

std::vector<glm::vec3> gridPositions(glm::ivec3 count, glm::vec3 origin, glm::vec3 spacing) {
    std::vector<glm::vec3> out;
    out.reserve(std::size_t(count.x) * std::size_t(count.y) * std::size_t(count.z));
    for (int z = 0; z < count.z; ++z)
        for (int y = 0; y < count.y; ++y)
            for (int x = 0; x < count.x; ++x)
                out.push_back(origin + glm::vec3(float(x), float(y), float(z)) * spacing);
    return out;
}

} // namespace rubble
