// host/world/blowup_check.cpp: host/dynamics/blowup_watch over a world's arrays.
#include "host/world/blowup_check.h"

#include <algorithm>

#include "host/dynamics/blowup_watch.h"
#include "host/world/device_step.h"
#include "host/world/world_state.h"

namespace rubble {

Status checkBlowUp(WorldState& s) {
    RUBBLE_TRY(syncHost(s));
    BlowUpWatch& w = s.blowUp;
    s.bodyRadii.resize(s.bodyCount());
    for (std::uint32_t i = 0; i < s.bodyCount(); ++i)
        s.bodyRadii[i] = s.shapes[s.shapeOf[i]].boundingRadius;
    BlowUpInputs in;
    in.poses = s.poses;
    in.velocities = s.velocities;
    in.momenta = s.momenta;
    in.masses = s.masses;
    in.radii = s.bodyRadii;
    in.gravity = s.options.gravity;
    in.dt = s.options.dt;
    in.baumgarte = s.options.solver.baumgarte;
    in.explicitEuler = s.options.integrator == Integrator::Explicit;
    in.eventsFired = std::size_t(std::count(s.eventFired.begin(), s.eventFired.end(), 1));
    in.step = s.step;
    std::optional<BlowUp> b = watchEnergy(w, in);
    if (!b && s.solver.jointsBuilt) b = watchJoints(s.solver.joints, s.poses, s.bodyRadii, s.step);
    if (!b) return {};
    return makeError(ErrorKind::Numerical, "body " + s.names[b->body], b->message);
}

} // namespace rubble
