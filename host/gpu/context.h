// host/gpu/context.h: one OpenCL device in use: its context, in-order queue, the program (built
// once per context, from the embedded text or RunOptions::kernelDir) and every kernel of it.
#pragma once

#include <CL/cl.h>

#include <array>
#include <memory>
#include <span>
#include <string>

#include "host/gpu/device.h"
#include "host/gpu/kernel_table.h"
#include "host/gpu/tuning.h"
#include "rubble/error.h"
#include "rubble/options.h"

namespace rubble::gpu {

class Context {
  public:
    /// Chooses the device of run.device, creates the context and queue, builds the program and
    /// creates its kernels. Errors: NotSupported with no OpenCL platform, BadInput for a device
    /// that does not exist or an unreadable kernel folder, Device for a failed call or a build
    /// that failed (the message holds the build log).
    static Result<std::shared_ptr<Context>> create(const RunOptions& run);
    /// The same with `tuning` in place of the device's defaults (host/gpu/tuning.h); a value
    /// the device cannot take is BadInput at `tuning <name>`.
    static Result<std::shared_ptr<Context>> create(const RunOptions& run,
                                                   std::span<const TuningValue> tuning);

    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    cl_context context() const { return context_; }
    cl_command_queue queue() const { return queue_; }
    cl_program program() const { return program_; }
    const DeviceInfo& device() const { return device_; }
    /// The tuning parameters the program was built and is dispatched with.
    const WorkSizes& workSizes() const { return sizes_; }
    cl_kernel kernel(KernelId id) const { return kernels_[static_cast<unsigned>(id)]; }
    /// Wall time of clBuildProgram, ms (PoCL's cache makes a second build much faster).
    double buildMs() const { return buildMs_; }
    /// "platform: device".
    std::string describe() const { return device_.platform + ": " + device_.name; }

  private:
    Context() = default;
    DeviceInfo device_;
    WorkSizes sizes_;
    cl_context context_ = nullptr;
    cl_command_queue queue_ = nullptr;
    cl_program program_ = nullptr;
    std::array<cl_kernel, static_cast<unsigned>(KernelId::Count)> kernels_{};
    double buildMs_ = 0;
};

/// The program text for run.kernelDir (with includes from <kernelDir>/../include, then the
/// embedded headers) or the embedded program.
Result<std::string> programSource(const RunOptions& run);

} // namespace rubble::gpu
