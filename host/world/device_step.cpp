// host/world/device_step.cpp: the OpenCL backend of a World over host/gpu's Pipeline.
#include "host/world/device_step.h"

#include "host/dynamics/forces.h"
#include "host/gpu/pipeline.h"
#include "host/world/world_state.h"

namespace rubble {

Status attachDevice(WorldState& s, std::shared_ptr<gpu::Context> context,
                    const SimulationOptions& options) {
    s.options = options;
    s.options.backend = Backend::OpenCl;
    RUBBLE_TRY(buildParticles(s));
    Result<gpu::PipelineHandle> p = gpu::Pipeline::create(std::move(context), s);
    RUBBLE_TRY(p);
    s.device = std::move(*p);
    s.hostStale = false;
    s.hostDirty = false;
    s.forcesDirty = false;
    return {};
}

Status syncHost(WorldState& s) {
    if (!s.device || !s.hostStale) return {};
    RUBBLE_TRY(s.device->downloadBodies(s));
    s.hostStale = false;
    return {};
}

Status beginHostChange(WorldState& s) {
    RUBBLE_TRY(syncHost(s));
    if (s.device) s.hostDirty = true;
    return {};
}

Status stepDevice(WorldState& s, StepStats& stats) {
    gpu::Pipeline& p = *s.device;
    // Events act on the host's copy of the momenta, which then goes back up.
    for (std::size_t e = 0; e < s.events.size(); ++e) {
        if (s.eventFired[e] || s.time() + 1e-9 < double(s.events[e].time)) continue;
        RUBBLE_TRY(beginHostChange(s));
        applyExplosion(s.events[e], s.poses, s.masses, s.momenta);
        s.eventFired[e] = 1;
    }
    if (s.hostDirty) {
        RUBBLE_TRY(p.uploadBodies(s));
        s.hostDirty = false;
    }
    if (s.forcesDirty) {
        RUBBLE_TRY(p.uploadForces(s.forces));
        s.forcesDirty = false;
    }
    const Status stepped = p.step(s, stats);
    s.hostStale = true;
    return stepped;
}

} // namespace rubble
