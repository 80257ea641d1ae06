// host/world/step_stop.h: where a step may end early: between its stages, when a stop was
// requested (RunOptions::stop), and the error of a step that ran out of memory.
#pragma once

#include "rubble/error.h"

namespace rubble {

struct WorldState;

/// ErrorKind::Interrupted naming the step when RunOptions::stop is set; else success. Checked
/// between the stages of the CPU step and before the device step.
Status checkStop(const WorldState& s);

/// ErrorKind::Limit for a step that ran out of memory (std::bad_alloc) in its stages.
Error outOfMemory(const WorldState& s);

} // namespace rubble
