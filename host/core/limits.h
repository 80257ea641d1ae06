// host/core/limits.h: what one step may allocate, and the largest inputs rubble reads. Pairs
// and contacts grow with the square of the bodies that overlap (1,000 boxes at one point: 1.9
// million contacts, 1.9 GB); the step budgets stop such a step with ErrorKind::Limit, naming the
// limit, before it runs out of memory. docs/scene-format.md, "Limits", states them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "rubble/error.h"

namespace rubble {

/// Broad-phase pairs per step: 64 per body on average above a floor, at most 2^24.
inline constexpr std::size_t kPairsPerBody = 64;
/// SAT contact points per step: 64 per body on average above a floor, and at most as many as
/// half the memory the process may use holds at kBytesPerContactPoint each (the
/// CPU step holds about that per point: manifold, rows, warm start; contactCap).
inline constexpr std::size_t kContactsPerBody = 64;
inline constexpr std::size_t kBytesPerContactPoint = 1024;
/// Particle contacts per step: 32 per particle on average above a floor (a sphere touches at
/// most 12 others of its size), at most 2^23, on the CPU and on the device.
inline constexpr std::size_t kContactsPerParticle = 32;
/// Every budget allows this many whatever the world's size.
inline constexpr std::size_t kBudgetFloor = 65536;
inline constexpr std::size_t kMaxPairs = std::size_t(1) << 24;
inline constexpr std::size_t kMaxParticleContacts = std::size_t(1) << 23;
/// Particles of a world (all bodies' together), and voxels of one shape while voxelising it.
inline constexpr std::size_t kMaxParticles = std::size_t(1) << 25;
inline constexpr double kMaxVoxels = double(std::size_t(1) << 24);
/// Ray-triangle tests while voxelising one shape: its voxels times its triangles.
inline constexpr double kMaxVoxelWork = 4e9;

/// The largest inputs rubble reads. A scene file's arrays and objects nest at most this deep
/// (deeper is refused while parsing, before anything walks the value recursively).
inline constexpr std::size_t kMaxJsonDepth = 64;
/// An OBJ mesh: its file size, vertices and triangles (after polygons are split). Building a
/// shape stays near-linear in these (host/geometry/half_edge.h).
inline constexpr std::size_t kMaxObjBytes = std::size_t(256) << 20;
inline constexpr std::size_t kMaxMeshVertices = 250'000;
inline constexpr std::size_t kMaxMeshTriangles = 500'000;

/// Bytes the process may use: the machine's physical memory, or the address-space or data
/// limit (RLIMIT_AS, RLIMIT_DATA) when one is lower. Read once.
std::uint64_t usableMemory();
/// The most SAT contact points a step may hold with `memory` bytes usable: half of it
/// at kBytesPerContactPoint each, never fewer than kBudgetFloor.
std::size_t contactCap(std::uint64_t memory);

/// The budgets of a world of `bodies` bodies and `particles` particles (the contact budget
/// capped by contactCap(usableMemory())).
std::size_t pairBudget(std::size_t bodies);
std::size_t contactBudget(std::size_t bodies);
std::size_t particleContactBudget(std::size_t particles);

/// ErrorKind::Limit at `where` (the stage), saying that `what` (e.g. "broad-phase pairs")
/// reached `count` in step `step` (1-based; 0 when not known), over the budget, with a hint of
/// the usual cause.
Error limitError(const std::string& where, const std::string& what, std::size_t count,
                 std::size_t budget, std::int64_t step, const std::string& hint);

} // namespace rubble
