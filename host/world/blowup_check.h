// host/world/blowup_check.h: the blow-up watches of host/dynamics/blowup_watch over a world's
// arrays, after each step.
#pragma once

#include "rubble/error.h"

namespace rubble {

struct WorldState;

/// Runs the energy and joint watches on the world's bodies after a step (the host arrays: a
/// device world reads its bodies back first). Errors: Numerical naming the body and the step.
Status checkBlowUp(WorldState& s);

} // namespace rubble
