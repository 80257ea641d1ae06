// host/gpu/step_start.h: the device state a step starts from, kept on the device so that a step
// the host did not wait for can run again from its start (device_step.cpp, "a step run ahead").
#pragma once

#include <span>
#include <vector>

#include "host/gpu/stage_queue.h"

namespace rubble::gpu {

/// Copies of a list of buffers, taken and put back by device-to-device copies in the step's
/// queue: no host memory and no wait.
class StepStart {
  public:
    /// Enqueues a copy of each of `state` (whole buffers) into a buffer of its own here; the
    /// list is remembered for restore(). Errors: Device, Limit.
    Status keep(StageQueue& q, std::span<const Buffer* const> state);
    /// Enqueues the copies back into the buffers kept from. Errors: Device.
    Status restore(StageQueue& q);

  private:
    std::vector<const Buffer*> kept_;
    std::vector<Buffer> copies_;
};

} // namespace rubble::gpu
