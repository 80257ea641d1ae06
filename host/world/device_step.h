// host/world/device_step.h: the OpenCL backend of a World: attaching a device pipeline, one
// step on it (beside the CPU world of an offloaded scene), and keeping the host's copy of the
// bodies current when someone asks for it.
#pragma once

#include <memory>

#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"

namespace rubble {

struct WorldState;
struct StepStats;
namespace gpu {
class Context;
}

/// Puts a whole world on the OpenCL backend of `context` (shared, so that tests and tools build
/// the program once) with the given options (backend set to opencl): sizes the device arrays and
/// uploads the bodies. When s.offload is set, its CPU-owned bodies are kinematic on the device.
/// Errors: NotSupported for options the device pipeline cannot run, Device.
Status attachDevice(WorldState& s, std::shared_ptr<gpu::Context> context,
                    const SimulationOptions& options);

/// Puts a world built from `scene` (all its bodies, in order) on the OpenCL backend of `context`
/// with the scene's options: the bodies the device does not step (host/world/offload.h,
/// deviceBodies) get a CPU world of their own, then attachDevice. Errors: those of
/// World::create and attachDevice.
Status attachScene(WorldState& s, const Scene& scene, std::shared_ptr<gpu::Context> context,
                   const RunOptions& run);

/// One step on the device: what the host changed (impulses, forces) is uploaded first, the
/// step is enqueued, the CPU world of an offloaded scene steps meanwhile, and the two meet.
/// Errors: Device, Numerical naming the body.
Status stepDevice(WorldState& s, StepStats& stats);

/// Reads the bodies back when the device stepped since the last read (World::body, writers).
/// Errors: Device.
Status syncHost(WorldState& s);

/// Makes the host arrays current and marks them changed, before the host writes into them.
Status beginHostChange(WorldState& s);

/// Kinematic body `i`'s velocity in the host's copy is new: the device's next step takes it
/// (a no-op without a device).
void noteKinematicVelocity(WorldState& s, std::uint32_t i);

} // namespace rubble
