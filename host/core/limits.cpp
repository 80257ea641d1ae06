// host/core/limits.cpp: the step budgets of host/core/limits.h and their error.
#include "host/core/limits.h"

#include <algorithm>

namespace rubble {
namespace {

std::size_t budget(std::size_t perItem, std::size_t items, std::size_t most) {
    return std::min(most, kBudgetFloor + perItem * items);
}

} // namespace

std::size_t pairBudget(std::size_t bodies) { return budget(kPairsPerBody, bodies, kMaxPairs); }
std::size_t contactBudget(std::size_t bodies) {
    return budget(kContactsPerBody, bodies, kMaxContacts);
}
std::size_t particleContactBudget(std::size_t particles) {
    return budget(kContactsPerParticle, particles, kMaxParticleContacts);
}

Error limitError(const std::string& where, const std::string& what, std::size_t count,
                 std::size_t limit, std::int64_t step, const std::string& hint) {
    return makeError(ErrorKind::Limit, where,
                     (step > 0 ? "step " + std::to_string(step) : std::string("the step")) +
                         " has more than " + std::to_string(limit) +
                         " " + what + " (" + std::to_string(count) +
                         " so far), the most one step may hold (docs/scene-format.md, Limits); " +
                         hint);
}

} // namespace rubble
