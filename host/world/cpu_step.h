// host/world/cpu_step.h: one step of the CPU pipeline (DESIGN.md, "One step, CPU reference"),
// stage by stage with a timer each, through the stage objects the world was built with.
#pragma once

#include "rubble/error.h"

namespace rubble {

struct WorldState;
struct StepStats;

/// Runs the stages on the world's arrays and fills `stats` (stage timings, contacts, residual,
/// bodies asleep). Before each stage after the first it checks RunOptions::stop. Errors: Limit
/// from the collision stages (pairs or contacts past their budget, host/core/limits.h), those
/// of the solver stage (a contact set a dense solver cannot take, no solution), Interrupted on a
/// stop request; the step is then left unfinished.
Status stepCpu(WorldState& s, StepStats& stats);

} // namespace rubble
