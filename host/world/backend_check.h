// host/world/backend_check.h: which backend, collision method and solver combinations run, and
// a clear refusal naming the option for those that do not.
#pragma once

#include "rubble/error.h"
#include "rubble/scene.h"

namespace rubble {

/// {sat, particles} x {pgs, jacobi, lcp-jacobi, lemke} on the cpu backend; particles with jacobi
/// or lcp-jacobi on opencl. Errors: NotSupported naming the scene field of the option that
/// cannot run with the others (SAT and PGS are CPU stages; the device pipeline has no joints).
Status checkBackendCombination(const Scene& scene);

} // namespace rubble
