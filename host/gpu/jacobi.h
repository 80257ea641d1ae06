// host/gpu/jacobi.h: the Jacobi family of solvers on the device for the particles' contacts
// (kernels/jacobi.cl, lcp_jacobi.cl): per-body row lists, warm start from last step's contacts,
// rows, the sweeps (or the dense problem of lcp-jacobi, host/gpu/lcp_jacobi.h), and the
// impulses into the momenta. The CPU twins are in host/dynamics/jacobi.cpp and lcp_jacobi.cpp.
#pragma once

#include <cstdint>

#include "host/gpu/device_bodies.h"
#include "host/gpu/lcp_jacobi.h"
#include "host/gpu/particles.h"
#include "rubble/shared/contact_row.h"

namespace rubble::gpu {

/// What each body is to the rows (bodies.jacobi): its inverse mass and world inverse inertia,
/// zero for a body that does not move (static, asleep, kinematic). PGS reads it too.
Status prepareJacobiBodies(StageQueue& q, DeviceBodies& b);

class JacobiSolve {
  public:
    /// Row lists per body, warm start (last step's contacts, `warmStart`), rows.
    Status buildRows(StageQueue& q, DeviceBodies& b, ContactBuffers& k, std::uint32_t particles,
                     const shared::SolverParams& params, bool warmStart);
    /// Copies the velocities to `before`, gathers the rows' impulses (warm start, or the dense
    /// solve's), then `iterations` sweeps (rows, then the gather); the momenta take up the
    /// velocity change.
    Status solve(StageQueue& q, DeviceBodies& b, ContactBuffers& k, int iterations,
                 float relaxation);
    /// lcp-jacobi: the dense problem from the rows (`stride` rows per contact, `k.count`
    /// contacts: the count must have been read), `iterations` sweeps, the impulses back into the
    /// rows; solve(0 iterations) then applies them. Errors: NotSupported past the dense
    /// problem's size, Device.
    Status solveDense(StageQueue& q, DeviceBodies& b, ContactBuffers& k, std::uint32_t stride,
                      int iterations, float relaxation);

  private:
    LcpBuffers lcp_;
};

} // namespace rubble::gpu
