// host/gpu/memory.cpp: the ledger of each context's buffers and the checks before a buffer is
// made.
#include "host/gpu/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <map>
#include <mutex>
#include <string>

namespace rubble::gpu {
namespace {

struct Ledger {
    MemoryLimits limits;
    std::uint64_t inUse = 0, peak = 0;
};

std::mutex& ledgerMutex() {
    static std::mutex m;
    return m;
}

std::map<cl_context, Ledger>& ledgers() {
    static std::map<cl_context, Ledger> l;
    return l;
}

std::string mib(std::uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
    return text;
}

// The process's address space now, bytes (/proc/self/statm's first field); 0 when unknown.
std::uint64_t addressSpace() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long long pages = 0;
    const int read = std::fscanf(f, "%llu", &pages);
    std::fclose(f);
    return read == 1 ? pages * std::uint64_t(sysconf(_SC_PAGESIZE)) : 0;
}

// Room the OpenCL implementation keeps beside a buffer's bytes in host memory (its own
// bookkeeping and the copies it makes while a command runs).
constexpr std::uint64_t kHostReserve = std::uint64_t(256) << 20;

} // namespace

void trackContext(cl_context context, const MemoryLimits& limits) {
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    ledgers()[context] = Ledger{limits, 0, 0};
}

void untrackContext(cl_context context) {
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    ledgers().erase(context);
}

Status admitBuffer(cl_context context, std::size_t bytes, std::size_t freed) {
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    const auto found = ledgers().find(context);
    if (found == ledgers().end()) return {};
    Ledger& l = found->second;
    if (l.limits.maxAllocation > 0 && bytes > l.limits.maxAllocation)
        return makeError(ErrorKind::Limit, "device memory",
                         "a buffer of " + mib(bytes) + " is larger than the device's largest (" +
                             mib(l.limits.maxAllocation) + ", CL_DEVICE_MAX_MEM_ALLOC_SIZE)");
    const std::uint64_t after = l.inUse - freed + bytes;
    if (l.limits.globalMemory > 0 && after > l.limits.globalMemory)
        return makeError(ErrorKind::Limit, "device memory",
                         "a buffer of " + mib(bytes) + " would take the buffers to " + mib(after) +
                             ", past the device's " + mib(l.limits.globalMemory) +
                             " (CL_DEVICE_GLOBAL_MEM_SIZE)");
    if (l.limits.hostMemory && bytes > freed) {
        rlimit limit{};
        if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
            const std::uint64_t used = addressSpace();
            const std::uint64_t need = used + (bytes - freed) + kHostReserve;
            if (used > 0 && need > limit.rlim_cur)
                return makeError(ErrorKind::Limit, "device memory",
                                 "a buffer of " + mib(bytes) + " in host memory would take the " +
                                     "process to " + mib(need) + " with the OpenCL runtime's " +
                                     "reserve, past its address-space limit of " +
                                     mib(limit.rlim_cur) + " (RLIMIT_AS, ulimit -v)");
        }
    }
    l.inUse = after;
    if (after > l.peak) l.peak = after;
    return {};
}

void releaseBuffer(cl_context context, std::size_t bytes) {
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    const auto found = ledgers().find(context);
    if (found == ledgers().end()) return;
    found->second.inUse -= std::min<std::uint64_t>(bytes, found->second.inUse);
}

std::uint64_t deviceBytesInUse(cl_context context) {
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    const auto found = ledgers().find(context);
    return found == ledgers().end() ? 0 : found->second.inUse;
}

std::uint64_t deviceBytesPeak(cl_context context) {
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    const auto found = ledgers().find(context);
    return found == ledgers().end() ? 0 : found->second.peak;
}

} // namespace rubble::gpu
