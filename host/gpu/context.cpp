// host/gpu/context.cpp: creating the context, queue, program and kernels of one device.
#include "host/gpu/context.h"

#include <algorithm>
#include <clblast.h>

#include <chrono>
#include <filesystem>

#include "host/core/clock.h"
#include "host/gpu/cl_check.h"
#include "host/gpu/embedded_kernels.h"
#include "host/gpu/kernel_source.h"
#include "host/gpu/memory.h"

namespace rubble::gpu {

Result<std::string> programSource(const RunOptions& run) {
    if (run.kernelDir.empty()) return std::string(kEmbeddedProgram);
    std::vector<SourceFile> headers;
    for (unsigned i = 0; i < kEmbeddedHeaderCount; ++i)
        headers.push_back({std::string(kEmbeddedHeaders[i].name),
                           std::string(kEmbeddedHeaders[i].text)});
    const std::string includeDir =
        (std::filesystem::path(run.kernelDir) / ".." / "include").lexically_normal().string();
    Result<std::string> text = programFromFolder(run.kernelDir, {includeDir}, headers);
    if (!text) {
        Error e = text.error();
        if (e.kind == ErrorKind::Io) e.kind = ErrorKind::BadInput;
        e.where = "--kernel-dir " + e.where;
        return e;
    }
    return text;
}

WorkSizes workSizesFor(const DeviceInfo& device) {
    auto floorPow2 = [](std::uint64_t x) {
        std::uint32_t p = 1;
        while (std::uint64_t(p) * 2 <= x && p < (1u << 30)) p *= 2;
        return p;
    };
    WorkSizes w;
    const std::uint32_t group =
        std::min<std::uint32_t>(64, floorPow2(std::max<std::uint64_t>(1, device.maxWorkGroupSize)));
    w.broadGroup = group;
    w.pairGroup = group;
    const std::uint64_t lanes = std::uint64_t(std::max<std::uint32_t>(1, device.computeUnits)) * 64;
    w.sortItems = std::clamp<std::uint32_t>(floorPow2(2 * lanes - 1), 256, 4096);
    w.pgsBlocks = device.cpu ? 4 * std::max<std::uint32_t>(1, device.computeUnits) : 0;
    w.contiguousItems = device.cpu;
    w.jointDouble = device.fp64;
    return w;
}

std::uint32_t defaultPgsBlocks(std::uint32_t deviceBlocks, std::size_t bodies) {
    if (deviceBlocks == 0) return 0;
    const std::size_t fit = std::max<std::size_t>(1, bodies / kPgsBlockBodies);
    return std::uint32_t(std::min<std::size_t>(deviceBlocks, fit));
}

std::string buildOptionsFor(const WorkSizes& sizes) {
    return std::string(kBuildOptions) + " -DRUBBLE_SORT_ITEMS=" + std::to_string(sizes.sortItems) +
           "u -DRUBBLE_GROUP_BROAD=" + std::to_string(sizes.broadGroup) +
           "u -DRUBBLE_GROUP_PAIRS=" + std::to_string(sizes.pairGroup) +
           "u -DRUBBLE_CONTIGUOUS_ITEMS=" + (sizes.contiguousItems ? "1" : "0") +
           " -DRUBBLE_JOINT_DOUBLE=" + (sizes.jointDouble ? "1" : "0");
}

Context::~Context() {
    // CLBlast keeps the programs it built (lcp-jacobi) in a cache of its own, released at exit
    // after this context otherwise: Oclgrind then frees them twice and aborts.
    if (queue_) clblast::ClearCache();
    for (cl_kernel k : kernels_)
        if (k) clReleaseKernel(k);
    if (program_) clReleaseProgram(program_);
    if (queue_) clReleaseCommandQueue(queue_);
    if (context_) {
        untrackContext(context_);
        clReleaseContext(context_);
    }
}

Result<std::shared_ptr<Context>> Context::create(const RunOptions& run) {
    Result<DeviceInfo> device = chooseDevice(run.device);
    RUBBLE_TRY(device);
    Result<std::string> source = programSource(run);
    RUBBLE_TRY(source);

    std::shared_ptr<Context> c(new Context());
    c->device_ = *device;
    c->sizes_ = workSizesFor(c->device_);
    cl_int err = CL_SUCCESS;
    const cl_context_properties props[] = {
        CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(c->device_.platformId), 0};
    RUBBLE_CL_CHECK((c->context_ = clCreateContext(props, 1, &c->device_.id, nullptr, nullptr, &err),
                     err));
    trackContext(c->context_, MemoryLimits{c->device_.maxAllocation, c->device_.globalMemory,
                                           c->device_.cpu});
    // Profiling is always on: every step reads its commands' device times (host/gpu/profile.h).
    RUBBLE_CL_CHECK((c->queue_ = clCreateCommandQueue(c->context_, c->device_.id,
                                                      CL_QUEUE_PROFILING_ENABLE, &err),
                     err));

    const char* text = source->c_str();
    const std::size_t length = source->size();
    RUBBLE_CL_CHECK(
        (c->program_ = clCreateProgramWithSource(c->context_, 1, &text, &length, &err), err));
    const auto start = std::chrono::steady_clock::now();
    const std::string options = run.buildOptions.empty()
                                    ? buildOptionsFor(c->sizes_)
                                    : buildOptionsFor(c->sizes_) + " " + run.buildOptions;
    const cl_int built =
        clBuildProgram(c->program_, 1, &c->device_.id, options.c_str(), nullptr, nullptr);
    c->buildMs_ = msSince(start);
    if (built != CL_SUCCESS) {
        std::size_t size = 0;
        std::string log;
        if (clGetProgramBuildInfo(c->program_, c->device_.id, CL_PROGRAM_BUILD_LOG, 0, nullptr,
                                  &size) == CL_SUCCESS) {
            log.resize(size);
            if (clGetProgramBuildInfo(c->program_, c->device_.id, CL_PROGRAM_BUILD_LOG, size,
                                      log.data(), nullptr) != CL_SUCCESS)
                log.clear();
        }
        while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
        Error e = clError("clBuildProgram", built);
        e.message = "the kernels " +
                    (run.kernelDir.empty() ? std::string("(embedded)")
                                           : "from " + run.kernelDir) +
                    " failed to build (" + clErrorName(built) + "); build log:\n" + log;
        return e;
    }
    for (const KernelSignature& s : kernelSignatures()) {
        const std::string name(s.name);
        cl_kernel& k = c->kernels_[static_cast<unsigned>(s.id)];
        k = clCreateKernel(c->program_, name.c_str(), &err);
        if (err != CL_SUCCESS) {
            Error e = clError("clCreateKernel", err);
            e.message = "kernel " + name + ": " + e.message;
            return e;
        }
    }
    return c;
}

} // namespace rubble::gpu
