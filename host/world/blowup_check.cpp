// host/world/blowup_check.cpp: host/dynamics/blowup_watch over a world's bodies after a step,
// or, on the device, over the device's sum of their energy until it nears the allowance.
#include "host/world/blowup_check.h"

#include <algorithm>

#include "host/dynamics/blowup_watch.h"
#include "host/gpu/pipeline.h"
#include "host/world/device_step.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// How far the device's float sum of the energy (sumBodyEnergy: each body's terms, a compensated
// sum per work-item, six levels of a tree) may lie from the watch's double sum of the same
// bodies, as a share of the sum of the terms' magnitudes: float's epsilon is 6e-8, this is about
// 170 of them.
constexpr double kDeviceRounding = 1e-5;

std::size_t eventsFired(const WorldState& s) {
    return std::size_t(std::count(s.eventFired.begin(), s.eventFired.end(), 1));
}

} // namespace

bool watchReadsBodies(const WorldState& s) {
    const BlowUpWatch& w = s.blowUp;
    return !s.deviceEnergy.known || !w.started || w.rebase || w.eventsFired != eventsFired(s) ||
           w.bodyAtLowest.size() != s.bodyCount() || s.deviceKinematic;
}

Status checkBlowUp(WorldState& s) {
    BlowUpWatch& w = s.blowUp;
    WorldState::DeviceEnergyWatch& d = s.deviceEnergy;
    // The device's sum of this step's energy, when the device steps every body and summed it.
    std::optional<std::pair<float, float>> summed;
    if (s.device && !s.offload) summed = s.device->energyOfLastStep();
    bool confirming = false;
    if (summed && !watchReadsBodies(s)) {
        const double energy = summed->first, rounding = kDeviceRounding * summed->second;
        if (energy < d.lowest) {
            d.lowest = energy;
            d.lowestRounding = rounding;
        }
        // Within the allowance whatever the rounding of both sums: the bodies stay on the device.
        const double allowed = w.allowance + w.explicitGain * double(s.step - w.since);
        if (energy - d.lowest <= allowed - 2.0 * (rounding + d.lowestRounding)) return {};
        // Near or past it: the watch on the bodies themselves confirms, from the highest the
        // lowest energy since the reference can be (so that rounding raises no false alarm), and
        // names the body that gained the most since the device's lowest sum.
        w.lowest = std::min(w.lowest, d.lowest + d.lowestRounding);
        RUBBLE_TRY(s.device->downloadLowestEnergies(w.bodyAtLowest));
        confirming = true;
    }
    RUBBLE_TRY(syncHost(s));
    BlowUpInputs in;
    in.bodies = s.bodies.view();
    in.shapes = s.shapes;
    in.gravity = s.options.gravity;
    in.dt = s.options.dt;
    in.baumgarte = s.options.solver.baumgarte;
    in.explicitEuler = s.options.integrator == Integrator::Explicit;
    in.eventsFired = eventsFired(s);
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
    if (summed && !confirming) {
        // The device's sums start again from this step's (as it kept this step's energies).
        d.lowest = summed->first;
        d.lowestRounding = kDeviceRounding * summed->second;
        d.known = true;
    }
    // A device world has no CPU solver; its jointed bodies step in its CPU world, watched there.
    if (!b && s.solver) b = watchJoints(s.solver->joints(), in.bodies, s.shapes, s.step);
    if (!b) return {};
    return makeError(ErrorKind::Numerical, "body " + s.names[b->body], b->message);
}

} // namespace rubble
