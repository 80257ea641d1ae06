// host/gpu/memory.cpp: the ledger of each context's buffers and the checks before a buffer is
// made.
#include "host/gpu/memory.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>

namespace rubble::gpu {
namespace {

struct Ledger {
    MemoryLimits limits;
    std::uint64_t inUse = 0, peak = 0;
    std::map<cl_mem, BufferRecord> buffers; ///< live buffers by handle
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

// Host allocations from this size up get pages of their own (glibc's M_MMAP_THRESHOLD, held at
// its starting value), bytes.
constexpr int kOwnPagesFrom = 128 << 10;

} // namespace

void trackContext(cl_context context, const MemoryLimits& limits) {
#if defined(__GLIBC__)
    // A CPU device's buffers are the OpenCL runtime's host allocations. glibc raises its mmap
    // threshold to the size of each mapped block freed (up to 32 MiB), so that after the first
    // regrowth the per-pair buffers land on the heap, where the blocks they replace stay
    // resident as holes; held at 128 KiB, every such block is mapped and its pages go back
    // when it is freed.
    if (limits.hostMemory) mallopt(M_MMAP_THRESHOLD, kOwnPagesFrom);
#endif
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    ledgers()[context] = Ledger{limits, 0, 0, {}};
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

void nameBuffer(cl_context context, cl_mem mem, std::size_t bytes, CallSite where) {
    // The path below host/gpu/ (or the whole name of a file elsewhere) and the line.
    std::string file = where.file;
    const std::size_t at = file.rfind("host/gpu/");
    if (at != std::string::npos) file.erase(0, at + 9);
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    const auto found = ledgers().find(context);
    if (found == ledgers().end()) return;
    found->second.buffers[mem] = BufferRecord{file + ":" + std::to_string(where.line), bytes};
}

void forgetBuffer(cl_context context, cl_mem mem) {
    const std::lock_guard<std::mutex> lock(ledgerMutex());
    const auto found = ledgers().find(context);
    if (found != ledgers().end()) found->second.buffers.erase(mem);
}

std::vector<BufferRecord> deviceBuffers(cl_context context) {
    std::vector<BufferRecord> out;
    {
        const std::lock_guard<std::mutex> lock(ledgerMutex());
        const auto found = ledgers().find(context);
        if (found == ledgers().end()) return out;
        for (const auto& [mem, record] : found->second.buffers) out.push_back(record);
    }
    std::sort(out.begin(), out.end(), [](const BufferRecord& a, const BufferRecord& b) {
        return a.bytes != b.bytes ? a.bytes > b.bytes : a.where < b.where;
    });
    return out;
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
