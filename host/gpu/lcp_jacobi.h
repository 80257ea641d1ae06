// host/gpu/lcp_jacobi.h: dispatch of OpenCL stage 5, dense variant (kernels/lcp_jacobi.cl and
// CLBlast's SGEMV): the dense problem from the device's contact rows or from the host, the
// projected Jacobi iteration, and the impulses back into the rows. The CPU twins are in
// host/dynamics/lcp_jacobi.cpp.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/gpu/buffer.h"
#include "host/gpu/context.h"

namespace rubble::gpu {

/// The dense problem on the device (host/dynamics/lcp_jacobi.h, DenseLcp, has the meaning of
/// each array), and a status block for the standalone iteration.
struct LcpBuffers {
    std::uint32_t contacts = 0, stride = 1;
    Buffer lcpRows, matrix, rhs, inverseScale, friction, lambda, product;
    Buffer status; ///< RUBBLE_STATUS_COUNT slots, for iterations outside a pipeline step

    std::uint32_t size() const { return contacts * stride; }
};

/// Stages buildLcpRows, assembleDelassus and scaleLcpRows on the device from `count` contact
/// rows (ContactRow) and the bodies' velocities before the solve, masses, flags (sleeping
/// bodies are walls) and poses. Errors: NotSupported past kLcpMaxRows rows, Device.
Status buildLcpOnDevice(const Context& c, const Buffer& rows, std::uint32_t count,
                        std::uint32_t stride, const Buffer& velocities, const Buffer& masses,
                        const Buffer& flags, const Buffer& poses, LcpBuffers& lcp);

/// A dense problem built on the host, as the arrays of the same names of DenseLcp
/// (host/dynamics/lcp_jacobi.h): size = contacts * stride.
struct HostLcp {
    std::uint32_t contacts = 0, stride = 1;
    std::span<const float> matrix;       ///< size^2, row-major
    std::span<const float> rhs;          ///< size
    std::span<const float> inverseScale; ///< size
    std::span<const float> friction;     ///< contacts
    std::span<const float> lambda;       ///< size
};

/// A problem built on the host (its rows are not needed) uploaded. Errors: Device.
Status uploadLcp(const Context& c, const HostLcp& p, LcpBuffers& lcp);

/// `iterations` sweeps of projected Jacobi: product = A lambda by CLBlast's SGEMV, then
/// projectLcp per contact. The last sweep's largest impulse change goes to `status`
/// (RUBBLE_STATUS_RESIDUAL, kept as the larger of it and what was there).
/// Errors: Device (naming the OpenCL call or CLBlast routine and its code).
Status iterateLcpJacobi(const Context& c, LcpBuffers& lcp, int iterations, float relaxation,
                        const Buffer& status);

/// The dense impulses into the contact rows' lambda. Errors: Device.
Status storeLcpImpulses(const Context& c, const LcpBuffers& lcp, const Buffer& rows);

/// Reads lambda (size() floats) back. Errors: Device.
Status downloadLcpLambda(const Context& c, const LcpBuffers& lcp, std::vector<float>& lambda);

/// Reads A (size()^2 floats, row-major) and b back, for twin tests. Errors: Device.
Status downloadLcpProblem(const Context& c, const LcpBuffers& lcp, std::vector<float>& matrix,
                          std::vector<float>& rhs, std::vector<float>& inverseScale);

} // namespace rubble::gpu
