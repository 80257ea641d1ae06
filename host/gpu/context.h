// host/gpu/context.h: one OpenCL device in use: its context, in-order queue, the program (built
// once per context, from the embedded text or RunOptions::kernelDir) and every kernel of it.
#pragma once

#include <CL/cl.h>

#include <array>
#include <memory>
#include <string>

#include "host/gpu/device.h"
#include "host/gpu/kernel_table.h"
#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/shared/constants.h"

namespace rubble::gpu {

/// Options every build of the program uses (the same text and options hit PoCL's binary cache);
/// the work sizes of the device follow them (buildOptionsFor).
inline constexpr const char* kBuildOptions = "-cl-kernel-arg-info -cl-std=CL1.2";

/// Work sizes and per-device constants that the kernels are built with (-D) and the host
/// dispatches with, derived from the device's limits (workSizesFor).
struct WorkSizes {
    std::uint32_t sortItems = RUBBLE_SORT_ITEMS;   ///< work-items of a radix sort pass
    std::uint32_t broadGroup = RUBBLE_GROUP_BROAD; ///< work-group of the SAT broad phase
    std::uint32_t pairGroup = RUBBLE_GROUP_PAIRS;  ///< work-group of the SAT narrow phase, pairs
    /// Blocks of the device's Gauss-Seidel solve (host/gpu/pgs.cpp): on a CPU device four per
    /// compute unit, each run in order by one work-item; 0 on a GPU, whose lanes want colors.
    std::uint32_t pgsBlocks = 0;
    /// Whether each work-item of a strided launch takes a run of consecutive items (a CPU
    /// device: one core goes through a group's work-items in turn) or its group's items one
    /// group-width apart (a GPU: adjacent lanes read adjacent items); RUBBLE_CONTIGUOUS_ITEMS,
    /// itemRangeItem in rubble/shared/group.h.
    bool contiguousItems = false;
    /// Whether the joints' position projection factors in double (RUBBLE_JOINT_DOUBLE, the
    /// JointReal of rubble/shared/cl_compat.h), as the CPU's does: on a device with fp64.
    bool jointDouble = false;
    /// Bytes of a JointReal on the device (the projection's matrices and solutions).
    std::uint32_t jointRealBytes() const { return jointDouble ? 8u : 4u; }
};

/// The work sizes for a device: work-groups of 64 (or the device's largest, if smaller: a
/// wavefront on AMD, two warps on NVIDIA, one vector loop of PoCL's CPU device), and a sort pass
/// of 64 work-items per compute unit, between 256 (what PoCL's two cores get) and 4096 (a
/// discrete GPU with 64 units), a power of two. None of these kernels uses local memory, so
/// CL_DEVICE_LOCAL_MEM_SIZE sets no limit yet.
WorkSizes workSizesFor(const DeviceInfo& device);

/// A block of the PGS solve holds at least this many bodies when the device chooses the count
/// (--pgs-blocks -1): a smaller world, below twice this, runs as one block, so that it sweeps its
/// rows in the CPU's order instead of coloring the elements between blocks, whose extra launches
/// cost more than a second thread saves there (docs/opencl.md, "Blocks").
inline constexpr std::uint32_t kPgsBlockBodies = 128;

/// The blocks of the PGS solve for a world of `bodies` bodies on a device that asks for
/// `deviceBlocks` (WorkSizes::pgsBlocks; 0, a GPU, stays 0).
std::uint32_t defaultPgsBlocks(std::uint32_t deviceBlocks, std::size_t bodies);

/// kBuildOptions followed by the work sizes as -D definitions.
std::string buildOptionsFor(const WorkSizes& sizes);

class Context {
  public:
    /// Chooses the device of run.device, creates the context and queue, builds the program and
    /// creates its kernels. Errors: NotSupported with no OpenCL platform, BadInput for a device
    /// that does not exist or an unreadable kernel folder, Device for a failed call or a build
    /// that failed (the message holds the build log).
    static Result<std::shared_ptr<Context>> create(const RunOptions& run);

    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    cl_context context() const { return context_; }
    cl_command_queue queue() const { return queue_; }
    cl_program program() const { return program_; }
    const DeviceInfo& device() const { return device_; }
    /// The work sizes the program was built with.
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
