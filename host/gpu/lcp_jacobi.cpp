// host/gpu/lcp_jacobi.cpp: dispatch of OpenCL stage 5, dense variant (kernels/lcp_jacobi.cl,
// CLBlast SGEMV). The CPU twins are in host/dynamics/lcp_jacobi.cpp. Argument order is the
// kernel signature's.
#include "host/gpu/lcp_jacobi.h"

#include <clblast.h>

#include <string>

#include "host/core/step_params.h"
#include "rubble/shared/lcp.h"

namespace rubble::gpu {
namespace {

// CLBlast's own codes (below -1000); the others are OpenCL's.
const char* clblastCodeName(int code) {
    switch (code) {
    case -1024: return "kNotImplemented";
    case -1022: return "kInvalidMatrixA";
    case -1019: return "kInvalidVectorX";
    case -1018: return "kInvalidVectorY";
    case -1017: return "kInvalidDimension";
    case -1016: return "kInvalidLeadDimA";
    case -1011: return "kInsufficientMemoryA";
    case -1008: return "kInsufficientMemoryX";
    case -1007: return "kInsufficientMemoryY";
    case -2046: return "kInvalidLocalMemUsage";
    case -2041: return "kDatabaseError";
    case -2040: return "kUnknownError";
    case -2039: return "kUnexpectedError";
    default: return code > -1000 ? clErrorName(code) : "unknown";
    }
}

Error clblastError(const char* routine, clblast::StatusCode status) {
    const int code = static_cast<int>(status);
    return makeError(ErrorKind::Device, routine,
                     std::string("failed with status ") + std::to_string(code) + " (" +
                         clblastCodeName(code) + ")");
}

Status reserveLcp(const Context& c, std::uint32_t contacts, std::uint32_t stride,
                  LcpBuffers& lcp) {
    lcp.contacts = contacts;
    lcp.stride = stride;
    const std::size_t n = lcp.size();
    RUBBLE_TRY(lcp.lcpRows.reserve(c.context(), n * sizeof(shared::LcpRow)));
    RUBBLE_TRY(lcp.matrix.reserve(c.context(), n * n * sizeof(float)));
    for (Buffer* b : {&lcp.rhs, &lcp.inverseScale, &lcp.lambda, &lcp.product})
        RUBBLE_TRY(b->reserve(c.context(), n * sizeof(float)));
    RUBBLE_TRY(lcp.friction.reserve(c.context(), contacts * sizeof(float)));
    // SGEMV forms beta y even for beta = 0: a NaN left in fresh memory would survive it.
    RUBBLE_TRY(fill(c, lcp.product, 0u, n * sizeof(float)));
    return lcp.status.reserve(c.context(), RUBBLE_STATUS_COUNT * sizeof(cl_uint));
}

} // namespace

Status buildLcpOnDevice(const Context& c, const Buffer& rows, std::uint32_t count,
                        std::uint32_t stride, const Buffer& velocities, const Buffer& masses,
                        const Buffer& flags, const Buffer& poses, LcpBuffers& lcp) {
    const std::size_t n = std::size_t(count) * stride;
    if (n > kLcpMaxRows)
        return makeError(ErrorKind::NotSupported, "lcp-jacobi",
                         "the lcp-jacobi solver takes at most " + std::to_string(kLcpMaxRows) +
                             " rows; this step has " + std::to_string(n) +
                             " (jacobi takes any number)");
    RUBBLE_TRY(reserveLcp(c, count, stride, lcp));
    if (n == 0) return {};
    const cl_uint size = cl_uint(n);
    RUBBLE_TRY(Dispatch(c, KernelId::BuildLcpRows)
                   .arg(cl_uint(count))
                   .arg(cl_uint(stride))
                   .arg(rows)
                   .arg(velocities)
                   .arg(masses)
                   .arg(flags)
                   .arg(poses)
                   .arg(lcp.lcpRows)
                   .arg(lcp.rhs)
                   .arg(lcp.lambda)
                   .arg(lcp.friction)
                   .run(count, RUBBLE_GROUP_CONTACTS));
    RUBBLE_TRY(Dispatch(c, KernelId::AssembleDelassus)
                   .arg(size)
                   .arg(lcp.lcpRows)
                   .arg(lcp.matrix)
                   .run(n * n, RUBBLE_GROUP_CONTACTS));
    return Dispatch(c, KernelId::ScaleLcpRows)
        .arg(size)
        .arg(lcp.matrix)
        .arg(lcp.inverseScale)
        .run(n, RUBBLE_GROUP_CONTACTS);
}

Status uploadLcp(const Context& c, const HostLcp& p, LcpBuffers& lcp) {
    RUBBLE_TRY(reserveLcp(c, p.contacts, p.stride, lcp));
    RUBBLE_TRY(fill(c, lcp.status, 0u, RUBBLE_STATUS_COUNT * sizeof(cl_uint)));
    RUBBLE_TRY(upload(c, lcp.matrix, p.matrix));
    RUBBLE_TRY(upload(c, lcp.rhs, p.rhs));
    RUBBLE_TRY(upload(c, lcp.inverseScale, p.inverseScale));
    RUBBLE_TRY(upload(c, lcp.friction, p.friction));
    return upload(c, lcp.lambda, p.lambda);
}

Status iterateLcpJacobi(const Context& c, LcpBuffers& lcp, int iterations, float relaxation,
                        const Buffer& status) {
    const std::size_t n = lcp.size();
    if (n == 0) return {};
    cl_command_queue queue = c.queue();
    for (int k = 0; k < iterations; ++k) {
        // product = A lambda: one right-hand side per step, so a matrix-vector product (GEMM
        // would only pay with several problems at once).
        const clblast::StatusCode gemv = clblast::Gemv<float>(
            clblast::Layout::kRowMajor, clblast::Transpose::kNo, n, n, 1.0f, lcp.matrix.mem(), 0,
            n, lcp.lambda.mem(), 0, 1, 0.0f, lcp.product.mem(), 0, 1, &queue, nullptr);
        if (gemv != clblast::StatusCode::kSuccess) return clblastError("clblast::Gemv", gemv);
        const cl_uint last = k + 1 == iterations ? 1u : 0u;
        RUBBLE_TRY(Dispatch(c, KernelId::ProjectLcp)
                       .arg(cl_uint(lcp.contacts))
                       .arg(cl_uint(lcp.stride))
                       .arg(lcp.product)
                       .arg(lcp.rhs)
                       .arg(lcp.inverseScale)
                       .arg(lcp.friction)
                       .arg(relaxation)
                       .arg(last)
                       .arg(lcp.lambda)
                       .arg(status)
                       .run(lcp.contacts, RUBBLE_GROUP_CONTACTS));
    }
    return {};
}

Status storeLcpImpulses(const Context& c, const LcpBuffers& lcp, const Buffer& rows) {
    if (lcp.contacts == 0) return {};
    return Dispatch(c, KernelId::StoreLcpImpulses)
        .arg(cl_uint(lcp.contacts))
        .arg(cl_uint(lcp.stride))
        .arg(lcp.lambda)
        .arg(rows)
        .run(lcp.contacts, RUBBLE_GROUP_CONTACTS);
}

Status downloadLcpLambda(const Context& c, const LcpBuffers& lcp, std::vector<float>& lambda) {
    lambda.resize(lcp.size());
    return download(c, lcp.lambda, std::span(lambda));
}

Status downloadLcpProblem(const Context& c, const LcpBuffers& lcp, std::vector<float>& matrix,
                          std::vector<float>& rhs, std::vector<float>& inverseScale) {
    const std::size_t n = lcp.size();
    matrix.resize(n * n);
    rhs.resize(n);
    inverseScale.resize(n);
    RUBBLE_TRY(download(c, lcp.matrix, std::span(matrix)));
    RUBBLE_TRY(download(c, lcp.rhs, std::span(rhs)));
    return download(c, lcp.inverseScale, std::span(inverseScale));
}


} // namespace rubble::gpu
