// host/gpu/lcp_convergence.h: the device solvers' iterates on one frozen contact set, the twins
// of jacobiIterates and lcpJacobiIterates (host/dynamics/lcp_convergence.h).
#pragma once

#include <memory>

#include "host/dynamics/lcp_convergence.h"
#include "host/gpu/context.h"

namespace rubble {
struct WorldState;
}

namespace rubble::gpu {

/// lcp-jacobi on the device from lambda = 0 (the problem uploaded once), lambda read back after
/// every sweep. Errors: Device.
Result<Iterates> lcpJacobiIteratesOnDevice(const Context& c, const DenseLcp& p, int iterations,
                                           float relaxation);

/// jacobi on the device: a pipeline for `s` (whose bodies are the set's: the world that
/// freezeContacts left), the set's contacts uploaded and their rows built without warm start,
/// then one sweep at a time, each from the same start velocities and the last rows, which is
/// the solve of `iterations` sweeps read back after each. Errors: Device.
Result<Iterates> jacobiIteratesOnDevice(std::shared_ptr<Context> c, const WorldState& s,
                                        const FrozenProblem& p, int iterations, float relaxation);

} // namespace rubble::gpu
