// host/world/frozen_contacts.h: one step's contact set taken from a world on the CPU pipeline,
// for comparing the solvers on it (`rubble solvers`, docs/solvers.md), and the device solvers'
// iterates on such a set, the twins of jacobiIterates and lcpJacobiIterates
// (host/dynamics/lcp_convergence.h).
#pragma once

#include <cstdint>
#include <memory>

#include "host/dynamics/lcp_convergence.h"
#include "rubble/world.h"

namespace rubble {

/// Steps a CPU world to just before the solve of step `step` (1-based): step - 1 whole steps,
/// then stages 1 to 4 of the next (forces, velocities, broad and narrow phase) with every body
/// woken first, so that the set also holds the contacts of bodies that were asleep. The world
/// is left mid-step: use it for nothing else.
/// Errors: BadInput for step < 1 or a world on the OpenCL backend; those of World::step.
Result<FrozenContacts> freezeContacts(World& world, std::int64_t step);

/// lcp-jacobi on the device from lambda = 0 (the problem uploaded once), lambda read back after
/// every sweep. Errors: Device.
Result<Iterates> lcpJacobiIteratesOnDevice(const gpu::Context& c, const DenseLcp& p,
                                           int iterations, float relaxation);

/// jacobi on the device: a pipeline for the set's bodies, its contacts uploaded and their rows
/// built without warm start, then one sweep at a time, each from the same start velocities and
/// the last rows, which is the solve of `iterations` sweeps read back after each.
/// Errors: Device.
Result<Iterates> jacobiIteratesOnDevice(std::shared_ptr<gpu::Context> c, const FrozenProblem& p,
                                        int iterations, float relaxation);

} // namespace rubble
