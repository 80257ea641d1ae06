// host/gpu/profile.h: the device time of every command of a step, from OpenCL profiling events:
// summed by stage for the step's StepStats, by kernel or transfer over the whole run, and kept
// command by command for the last step (rubble run --trace).
#pragma once

#include <CL/cl.h>

#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "host/gpu/kernel_table.h"
#include "host/gpu/traffic.h"
#include "rubble/error.h"
#include "rubble/world.h"

namespace rubble::gpu {

/// Commands that are not kernels, counted beside them.
enum class Transfer : unsigned { Write, Read, Copy, Fill, Count };

/// The stage a command belongs to, in the order of kDeviceStageFields (rubble/world.h), which
/// names it and gives its field of DeviceStageMs.
enum class DeviceStage : unsigned {
    ApplyForces,
    IntegrateVelocities,
    BroadPhase,
    NarrowPhase,
    BuildContactRows,
    Solve,
    IntegratePositions,
    Sleep,
    Count
};

/// One kernel's or transfer's totals over the run.
struct CommandTotals {
    std::string_view name;
    double ms = 0;            ///< device time, from CL_PROFILING_COMMAND_START to _END
    std::uint64_t launches = 0;
    std::uint64_t bytes = 0; ///< bytes moved: a transfer's, or a kernel's (host/gpu/traffic.h)
};

/// The name of a stage as the metrics' device_stages_ms has it (`build_contact_rows`).
std::string_view stageName(DeviceStage stage);

/// The device's clock against the host's steady clock: the CL_PROFILING_COMMAND_QUEUED time of a
/// marker, taken when the host enqueues it, and the host's time just before and after the
/// enqueue; of `tries` markers, the one whose enqueue took least. Waits for the queue to empty.
/// Errors: Device.
Result<DeviceClockSample> sampleClock(cl_command_queue queue, int tries = 20);

/// What one step's commands took on the device.
struct DeviceTimes {
    double busyMs = 0;   ///< sum of the commands' durations
    double spanMs = 0;   ///< first start to last end
    DeviceStageMs stages;
};

/// Collects the events of one step's commands; the host reads their times once the step is done.
class Profile {
  public:
    Profile();
    ~Profile();
    Profile(const Profile&) = delete;
    Profile& operator=(const Profile&) = delete;

    /// Commands recorded from now on belong to `stage`.
    void setStage(DeviceStage stage) { stage_ = stage; }
    DeviceStage stage() const { return stage_; }
    /// The event slot of the next command, a kernel or a transfer of `bytes`.
    cl_event* kernel(KernelId id);
    cl_event* transfer(Transfer kind, std::size_t bytes);
    /// The bytes of the command recorded last, for a kernel whose traffic the counts of
    /// collect() do not give (exclusiveScan).
    void setLastBytes(std::size_t bytes);
    /// Counts a time the host waited for the device: a blocking transfer, a finish.
    void countWait() { ++waits_; }
    /// The waits counted so far.
    std::uint64_t waits() const { return waits_; }

    /// Reads the times of the recorded commands (all of them must have completed), adds them to
    /// the run's totals (kernels with the bytes kernelBytes gives for `counts`), releases their
    /// events and returns the step's figures. Errors: Device.
    Result<DeviceTimes> collect(const TrafficCounts& counts = {});
    /// Releases the recorded events without reading them (a step that failed).
    void discard();
    /// Whether collect() keeps each command's times for lastCommands() (two more queries per
    /// command: only while someone reads them, rubble run --trace).
    void keepCommands(bool keep) { keepCommands_ = keep; }
    /// The commands the last collect() read, in the order they were enqueued (none unless kept).
    std::span<const DeviceCommand> lastCommands() const { return lastCommands_; }

    /// Totals over the run, kernels in KernelId order then transfers; commands never run are
    /// left out.
    std::vector<CommandTotals> totals() const;
    /// Adds another profile's totals to these.
    void addTotals(const Profile& other);

  private:
    struct Record {
        unsigned command;   ///< KernelId, or KernelId::Count + Transfer
        DeviceStage stage;
        std::size_t bytes;
        cl_event event;
    };
    cl_event* add(unsigned command, std::size_t bytes);
    DeviceStage stage_ = DeviceStage::ApplyForces;
    std::vector<Record> records_;
    bool keepCommands_ = false;
    std::vector<DeviceCommand> lastCommands_; // reused: a warm step allocates nothing
    std::vector<CommandTotals> totals_;
    std::uint64_t waits_ = 0;
};

} // namespace rubble::gpu
