// host/scene/generators.h: scene generators that add bodies (SCENE_FORMAT.md, `generators`).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace rubble {

/// Rotations drawn for the grid generator. The draws are defined here, not by the standard
/// library's distributions (whose output differs between implementations), so that any tool can
/// reproduce a scene: std::mt19937 seeded with `seed`; each body takes three 32-bit outputs
/// u1, u2, u3, each mapped to [0, 1) as (u >> 8) / 2^24; the axis is
/// (sqrt(1 - z^2) cos(phi), sqrt(1 - z^2) sin(phi), z) with z = 2 u1 - 1, phi = 2 pi u2, and the
/// angle is (2 u3 - 1) jitter.
std::vector<glm::quat> jitterRotations(std::uint32_t seed, std::size_t count, float jitter);

/// Positions of a grid of count.x * count.y * count.z bodies from origin with spacing (m),
/// x fastest, then y, then z.
std::vector<glm::vec3> gridPositions(glm::ivec3 count, glm::vec3 origin, glm::vec3 spacing);

} // namespace rubble
