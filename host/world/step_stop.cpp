// host/world/step_stop.cpp: the check between the stages of a step (host/world/step_stop.h).
#include "host/world/step_stop.h"

#include "host/world/world_state.h"

namespace rubble {

bool stepMustStop(WorldState& s) {
    if (s.stepFailure) return true;
    if (!s.run.stop || !s.run.stop->load(std::memory_order_relaxed)) return false;
    s.stepFailure = makeError(ErrorKind::Interrupted, "step " + std::to_string(s.step + 1),
                              "stopped on request before its end; the state is that after step " +
                                  std::to_string(s.step));
    return true;
}

Error outOfMemory(const WorldState& s) {
    return makeError(ErrorKind::Limit, "step " + std::to_string(s.step + 1),
                     "ran out of memory (" + std::to_string(s.bodyCount()) + " bodies, " +
                         std::to_string(s.pairs.size()) + " pairs, " +
                         std::to_string(s.manifolds.size()) +
                         " manifolds); stepping further is meaningless");
}

} // namespace rubble
