// host/world/step_stop.cpp: the check between the stages of a step (host/world/step_stop.h).
#include "host/world/step_stop.h"

#include "host/world/world_state.h"

namespace rubble {

Status checkStop(const WorldState& s) {
    if (!s.run.stop || !s.run.stop->load(std::memory_order_relaxed)) return {};
    return makeError(ErrorKind::Interrupted, "step " + std::to_string(s.step + 1),
                     "stopped on request between two of its stages; the bodies are left "
                     "part-way through it (the state after step " +
                         std::to_string(s.step) + " is no longer held)");
}

Error outOfMemory(const WorldState& s) {
    return makeError(ErrorKind::Limit, "step " + std::to_string(s.step + 1),
                     "ran out of memory (" + std::to_string(s.bodyCount()) + " bodies, " +
                         std::to_string(s.contacts.pairs.size()) + " pairs, " +
                         std::to_string(s.contacts.contactCount) +
                         " contact points); stepping further is meaningless");
}

} // namespace rubble
