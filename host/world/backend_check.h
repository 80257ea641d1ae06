// host/world/backend_check.h: which backend, collision method and solver combinations run, and
// a clear refusal naming the option for those that do not.
#pragma once

#include "rubble/error.h"
#include "rubble/scene.h"

namespace rubble {

/// {sat, particles} x {pgs, jacobi, lcp-jacobi, lemke} on the cpu backend; on opencl, sat with
/// pgs (every body on the device, joints too; asked for by naming sat) and particles with jacobi
/// or lcp-jacobi (jointed bodies, or those outside a debris set, step on the CPU:
/// host/world/offload.h; a debris set's pgs is the CPU bodies' and the set takes jacobi). Joints
/// need pgs wherever their bodies step with the scene's solver.
/// Errors: NotSupported naming the scene field of the option that cannot run with the others
/// (particles with pgs named on opencl without a debris set: collision.method, with the fix),
/// or a joint on a body of the debris set (the device's particle path has no joint rows).
Status checkBackendCombination(const Scene& scene);

} // namespace rubble
