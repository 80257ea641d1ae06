// host/collision/particles.h: the particle collision method's data and OpenCL stages
// transformParticles and collideParticles on the CPU, twins of kernels/particles.cl (dispatch in
// host/gpu/particles.cpp) with the per-element math of rubble/shared/particle.h.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "host/collision/contact.h"
#include "host/collision/grid.h"
#include "host/core/bodies.h"
#include "host/geometry/shape.h"
#include "rubble/error.h"
#include "rubble/shared/particle.h"

namespace rubble {

/// The particles of a world's bodies and the static shapes they meet, made once at load (and
/// again when bodies are added or removed).
struct ParticleSet {
    float cellSize = 0;                       ///< m: the largest particle diameter + margin
    float margin = 0;                         ///< m: contacts are made this far apart
    std::uint32_t bits = 0;                   ///< the grid hash table has 2^bits cells
    std::vector<shared::Particle> particles;  ///< grouped by body, in body order
    std::vector<shared::StaticShape> statics; ///< planes and static boxes, met analytically
};

/// Voxelises each shape once (surface particles only, `spacing` apart) and gives every body
/// except planes and static boxes its shape's particles; planes and static boxes become static
/// shapes (at their poses, with their materials' friction and restitution). Errors: BadInput at
/// simulation.collision.particle_spacing when the world would need more particles than a
/// device buffer index can address; Limit there when a shape would take more voxels or ray
/// tests, or the world more particles, than host/core/limits.h allows (checked before they are
/// made); NotSupported past RUBBLE_MAX_STATIC_SHAPES static shapes. For the contacts of PGS
/// (`pgs`): contacts are made while two particles (or a particle and a static shape) are less
/// than kParticleContactMargin apart (the grid's cells grow by it), and a shape's particles come
/// in a fixed scattered order rather than the voxeliser's rows (Gauss-Seidel sweeps a pair's
/// contacts in particle order); for the Jacobi solvers neither.
Result<ParticleSet> buildParticleSet(std::span<const Shape> shapes,
                                     std::span<const MaterialDesc> materials, BodiesView bodies,
                                     float spacing, bool pgs);

/// How far apart two particles (or a particle and a static shape) still make a contact for PGS,
/// m: a speculative gap, so that bodies that rest touching, at a gap of zero, meet from the
/// first step. A quarter of the SAT method's RUBBLE_CONTACT_MARGIN: a face of fine particles
/// has many within 4 mm of what it rests on, and each is a row and a restless neighbour
/// (docs/opencl.md, "Particle contacts into PGS").
constexpr float kParticleContactMargin = 0.001f;

/// Stage transformParticles. reads: particles, poses   writes: world
void transformParticles(std::span<const shared::Particle> particles,
                        std::span<const shared::BodyPose> poses, std::span<shared::float4> world);
/// The same, leaving the particles of sleeping bodies where they are, as the device does.
/// reads: particles, poses, masses (flags)   writes: world
void transformParticles(std::span<const shared::Particle> particles,
                        std::span<const shared::BodyPose> poses,
                        std::span<const shared::BodyMass> masses, std::span<shared::float4> world);

/// Stage collideParticles: each particle of a body that tests pairs (testsPairsItem: an awake
/// dynamic body) against the particles of other bodies in its 27 neighbouring cells and against
/// the static shapes. Which side tests a pair: pairFromHereItem (two awake bodies' pair once,
/// from the particle sorted first); body a of a contact is the awake body, or the lower index
/// of two awake ones. Appends to `contacts` in sorted-slot order. Stops and returns false once
/// it has found more than `maxContacts` (host/core/limits.h).
/// reads: set, world, grid, masses   writes: contacts
bool collideParticles(const ParticleSet& set, std::span<const shared::float4> world,
                      const ParticleGrid& grid, std::span<const shared::BodyMass> masses,
                      std::vector<shared::ParticleContact>& contacts,
                      std::size_t maxContacts = std::numeric_limits<std::size_t>::max());

/// Orders contacts by their particle a, then by feature b (the pair names a contact): the
/// device's deterministic mode gives the same order, and so the same sums.
void sortContactsByParticle(std::vector<shared::ParticleContact>& contacts);

/// Particle contacts as single-point manifolds for the PGS solver (a < b, the normal flipped
/// when the bodies swap), the feature id from the two particles.
void particleContactsToManifolds(std::span<const shared::ParticleContact> contacts,
                                 std::vector<Manifold>& manifolds);

} // namespace rubble
