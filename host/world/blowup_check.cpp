// host/world/blowup_check.cpp: host/dynamics/blowup_watch over a world's bodies after a step.
#include "host/world/blowup_check.h"

#include <algorithm>

#include "host/dynamics/blowup_watch.h"
#include "host/world/device_step.h"
#include "host/world/world_state.h"

namespace rubble {

Status checkBlowUp(WorldState& s) {
    RUBBLE_TRY(syncHost(s));
    BlowUpInputs in;
    in.bodies = s.bodies.view();
    in.shapes = s.shapes;
    in.gravity = s.options.gravity;
    in.dt = s.options.dt;
    in.baumgarte = s.options.solver.baumgarte;
    in.explicitEuler = s.options.integrator == Integrator::Explicit;
    in.eventsFired = std::size_t(std::count(s.eventFired.begin(), s.eventFired.end(), 1));
    in.step = s.step;
    // A moving kinematic body does work on what it pushes or carries: the energy it puts in is
    // the host's, as a force's is, and the watch starts again from this step.
    for (std::uint32_t i = 0; i < s.bodyCount(); ++i) {
        const BodyVelocity& v = s.bodies.velocities[i];
        if ((s.bodies.masses[i].flags & RUBBLE_BODY_KINEMATIC) &&
            (shared::dot3(v.linear, v.linear) > 0.0f || shared::dot3(v.angular, v.angular) > 0.0f))
            s.blowUp.rebase = true;
    }
    std::optional<BlowUp> b = watchEnergy(s.blowUp, in);
    // A device world has no CPU solver; its jointed bodies step in its CPU world, watched there.
    if (!b && s.solver) b = watchJoints(s.solver->joints(), in.bodies, s.shapes, s.step);
    if (!b) return {};
    return makeError(ErrorKind::Numerical, "body " + s.names[b->body], b->message);
}

} // namespace rubble
