// host/gpu/context.cpp: creating the context, queue, program and kernels of one device.
#include "host/gpu/context.h"

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
    return create(run, {});
}

Result<std::shared_ptr<Context>> Context::create(const RunOptions& run,
                                                 std::span<const TuningValue> tuning) {
    Result<DeviceInfo> device = chooseDevice(run.device);
    RUBBLE_TRY(device);
    Result<WorkSizes> sizes = tunedWorkSizes(workSizesFor(*device), tuning, *device);
    RUBBLE_TRY(sizes);
    Result<std::string> source = programSource(run);
    RUBBLE_TRY(source);

    std::shared_ptr<Context> c(new Context());
    c->device_ = *device;
    c->sizes_ = *sizes;
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
