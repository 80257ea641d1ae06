// host/core/limits.cpp: the step budgets of host/core/limits.h and their error.
#include "host/core/limits.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>

namespace rubble {
namespace {

std::size_t budget(std::size_t perItem, std::size_t items, std::size_t most) {
    return std::min(most, kBudgetFloor + perItem * items);
}

} // namespace

std::size_t pairBudget(std::size_t bodies) { return budget(kPairsPerBody, bodies, kMaxPairs); }
std::uint64_t usableMemory() {
    static const std::uint64_t memory = [] {
        const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
        std::uint64_t most = pages > 0 && pageSize > 0
                                 ? std::uint64_t(pages) * std::uint64_t(pageSize)
                                 : std::uint64_t(1) << 32; // not known: assume 4 GiB
        for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
            rlimit limit{};
            if (getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
                most = std::min<std::uint64_t>(most, limit.rlim_cur);
        }
        return most;
    }();
    return memory;
}

std::size_t contactCap(std::uint64_t memory) {
    return std::max<std::size_t>(kBudgetFloor,
                                 std::size_t(memory / 2 / kBytesPerContactPoint));
}

std::size_t contactBudget(std::size_t bodies) {
    return budget(kContactsPerBody, bodies, contactCap(usableMemory()));
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
