// host/world/blowup_check.h: the blow-up watches of host/dynamics/blowup_watch over a world's
// arrays, after each step.
#pragma once

#include "rubble/error.h"

namespace rubble {

struct WorldState;

/// Runs the energy and joint watches on the world's bodies after a step (the host arrays: a
/// device world reads its bodies back first). A device world whose step summed the bodies'
/// energy (gpu::StepInputs::sumEnergy) watches that sum instead and reads the bodies only when
/// it comes within its rounding of the allowance, to confirm on the bodies and name the body.
/// Errors: Numerical naming the body and the step.
Status checkBlowUp(WorldState& s);

/// Whether the next check of a device world reads the bodies whatever the device's sum: the
/// watch starts again (its first step, an explosion, energy from the host) or kinematic bodies
/// move the host's way.
bool watchReadsBodies(const WorldState& s);

} // namespace rubble
