// host/collision/particle_world.h: the particle collision method on the CPU, OpenCL stages 2 to
// 4 (transformParticles, buildGrid, collideParticles) as twins of kernels/particles.cl and
// kernels/grid.cl, with the per-element math of rubble/shared/particle.h.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "host/collision/contact.h"
#include "rubble/error.h"
#include "rubble/shared/particle.h"

namespace rubble {

struct WorldState;

/// The particles of a world and the grid over them. Made once at load (particles, statics);
/// the rest is rewritten every step.
struct ParticleState {
    bool built = false;
    float cellSize = 0;   ///< m: the largest particle diameter
    std::uint32_t bits = 0; ///< the grid hash table has 2^bits cells
    std::vector<shared::Particle> particles;  ///< grouped by body, in body order
    std::vector<shared::StaticShape> statics; ///< planes and static boxes, met analytically
    std::vector<shared::float4> world;        ///< world positions (w = radius), per particle
    std::vector<std::uint32_t> keys;          ///< cell keys, sorted
    std::vector<std::uint32_t> order;         ///< particle of each sorted slot
    std::vector<std::uint32_t> cellStart, cellEnd; ///< sorted slots of each cell, or empty
    std::vector<shared::ParticleContact> contacts;
};

/// Voxelises each shape once (spacing from the options, surface particles only) and gives every
/// body except planes and static boxes its shape's particles; planes and static boxes become
/// static shapes. Errors: BadInput at simulation.collision.particle_spacing when the world
/// would need more particles than a device buffer index can address; Limit there when a shape
/// would take more voxels or ray tests, or the world more particles, than host/core/limits.h
/// allows (checked before they are made).
Status buildParticles(WorldState& s);

/// Grid hash table size for a particle count: 2^bits >= 2 count, 2^10 .. 2^24.
std::uint32_t gridBits(std::size_t particleCount);

/// Stage transformParticles. reads: particles, poses   writes: world
void transformParticles(std::span<const shared::Particle> particles,
                        std::span<const shared::BodyPose> poses, std::span<shared::float4> world);
/// The same, leaving the particles of sleeping bodies where they are, as the device does.
/// reads: particles, poses, masses (flags)   writes: world
void transformParticles(std::span<const shared::Particle> particles,
                        std::span<const shared::BodyPose> poses,
                        std::span<const shared::BodyMass> masses, std::span<shared::float4> world);

/// Stage buildGrid: cell keys, a stable sort of the particles by key (the device's LSD radix
/// sort gives the same order), each cell's range of sorted slots.
/// reads: world   writes: keys, order, cellStart, cellEnd
void buildGrid(std::span<const shared::float4> world, float cellSize, std::uint32_t bits,
               std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>& order,
               std::vector<std::uint32_t>& cellStart, std::vector<std::uint32_t>& cellEnd);

/// Stage collideParticles: each particle of a body that tests pairs (testsPairsItem: an awake
/// dynamic body) against the particles of other bodies in its 27 neighbouring cells and against
/// the static shapes. Which side tests a pair: pairFromHereItem (two awake bodies' pair once,
/// from the particle sorted first); body a of a contact is the awake body, or the lower index
/// of two awake ones. Appends to `contacts` in sorted-slot order.
/// Stops and returns false once it has found more than `maxContacts` (host/core/limits.h).
/// reads: world, particles, grid, statics, masses   writes: contacts
bool collideParticles(const ParticleState& p, std::span<const shared::BodyMass> masses,
                      std::vector<shared::ParticleContact>& contacts,
                      std::size_t maxContacts = std::numeric_limits<std::size_t>::max());

/// Orders contacts by their particle a, then by feature b (the pair names a contact): the
/// device's deterministic mode gives the same order, and so the same sums.
void sortContactsByParticle(std::vector<shared::ParticleContact>& contacts);

/// Particle contacts as single-point manifolds for the PGS solver (a < b, the normal flipped
/// when the bodies swap), the feature id from the two particles.
void particleContactsToManifolds(std::span<const shared::ParticleContact> contacts,
                                 std::vector<Manifold>& manifolds);

/// Stages buildGrid's and collideParticles' world versions: transform, grid, collide into
/// s.particles, and stats (contact count, largest penetration).
void runParticleGrid(WorldState& s);
void runParticleCollide(WorldState& s);

} // namespace rubble
