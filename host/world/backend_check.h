// host/world/backend_check.h: which backend, collision method and solver combinations run, and
// a clear refusal naming the option for those that do not.
#pragma once

#include "rubble/error.h"
#include "rubble/scene.h"

namespace rubble {

/// {sat, particles} x {pgs, jacobi, lcp-jacobi, lemke} on the cpu backend; particles with jacobi
/// or lcp-jacobi on opencl, where jointed bodies step on the CPU (host/world/offload.h); pgs on
/// opencl in a scene with a debris set (its CPU bodies step with PGS, the set with jacobi).
/// Joints need pgs on the cpu backend: jacobi, lcp-jacobi and lemke have contact rows only.
/// Errors: NotSupported naming the scene field of the option that cannot run with the others
/// (SAT and PGS are CPU stages; a joint with a solver that has no joint rows), or a joint on a
/// body of the debris set (the device has no joint rows).
Status checkBackendCombination(const Scene& scene);

} // namespace rubble
