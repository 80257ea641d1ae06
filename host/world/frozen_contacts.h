// host/world/frozen_contacts.h: one step's contact set taken from a world on the CPU reference
// pipeline, for comparing the solvers on it (`rubble solvers`, docs/solvers.md).
#pragma once

#include <cstdint>

#include "host/dynamics/lcp_convergence.h"
#include "rubble/world.h"

namespace rubble {

/// Steps a CPU world to just before the solve of step `step` (1-based): step - 1 whole steps,
/// then stages 1 to 4 of the next (forces, velocities, broad and narrow phase) with every body
/// woken first, so that the set also holds the contacts of bodies that were asleep. The world
/// is left mid-step: use it for nothing else but the contact set's device twin.
/// Errors: BadInput for step < 1 or a world on the OpenCL backend; those of World::step.
Result<FrozenContacts> freezeContacts(World& world, std::int64_t step);

} // namespace rubble
