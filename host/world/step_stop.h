// host/world/step_stop.h: where a step may end early: between its stages, when a stage could not
// run (a budget of host/core/limits.h, a dense solver's size) or a stop was requested.
#pragma once

#include "rubble/error.h"

namespace rubble {

struct WorldState;

/// True when the step must end before its next stage: a stage set s.stepFailure, or
/// RunOptions::stop is set (s.stepFailure then becomes ErrorKind::Interrupted, naming the step).
bool stepMustStop(WorldState& s);

/// ErrorKind::Limit for a step that ran out of memory (std::bad_alloc) in its stages.
Error outOfMemory(const WorldState& s);

} // namespace rubble
