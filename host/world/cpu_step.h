// host/world/cpu_step.h: one step of the CPU reference pipeline (DESIGN.md, "One step, CPU
// reference"), stage by stage with a timer each.
#pragma once

namespace rubble {

struct WorldState;
struct StepStats;

/// Runs stages 1 to 7 on the world's arrays and fills the stage timings of `stats`.
void stepCpuReference(WorldState& s, StepStats& stats);

} // namespace rubble
