// host/io/trace.h: `rubble run --trace FILE.json`: the OpenCL device's commands of every step as a
// Chrome trace (the Trace Event Format that chrome://tracing and ui.perfetto.dev open).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "host/core/clock.h"
#include "rubble/error.h"
#include "rubble/world.h"

namespace rubble {

/// Collects the device's commands step by step while a world runs on the opencl backend, then
/// writes them as trace events: one complete event ("ph": "X") per command on the device's
/// queue (tid 1), and one per step on the host (tid 2) spanning World::step, placed on the
/// device's clock through two DeviceClockSample taken before the first step and after the last.
/// Keeps 72 bytes per command and 32 per step; the text written at the end is about 175 bytes
/// per command.
class TraceRecorder {
  public:
    /// Has the world keep its steps' device commands and relates the clocks before the first
    /// step. Errors: NotSupported on the cpu backend, Device.
    Status start(World& world);
    /// Records the step that just ran: its device commands, and its host span, the wall time
    /// from `begin` to `end` around World::step.
    void afterStep(const World& world, Clock::time_point begin, Clock::time_point end);
    /// Relates the clocks again after the last step, for the drift written with the trace.
    /// Errors: Device.
    Status finish(const World& world);

    /// Commands recorded.
    std::size_t commands() const { return commands_.size(); }
    /// The trace as JSON text.
    std::string toJson(const World& world) const;

  private:
    struct Command {
        std::uint32_t step;
        DeviceCommand command;
    };
    struct HostStep {
        std::uint32_t step;
        std::int64_t begin, end; // steady clock, ns
        double waitMs;           // the host's wait for the device in the step
    };
    std::vector<Command> commands_;
    std::vector<HostStep> steps_;
    DeviceClockSample first_, last_;
    bool finished_ = false;
};

} // namespace rubble
