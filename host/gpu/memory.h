// host/gpu/memory.h: the device memory a context's buffers hold, checked before each buffer is
// made against what the device and the process allow: the device's largest allocation
// (CL_DEVICE_MAX_MEM_ALLOC_SIZE), its global memory (CL_DEVICE_GLOBAL_MEM_SIZE), and, for a
// device whose buffers live in host memory (a CPU device), the process's address-space limit
// (RLIMIT_AS). A buffer that would not fit is refused with ErrorKind::Limit instead of failing
// inside the OpenCL implementation (PoCL aborts when its host allocation fails).
#pragma once

#include <CL/cl.h>

#include <cstdint>
#include <string>
#include <vector>

#include "rubble/error.h"

namespace rubble::gpu {

struct MemoryLimits {
    std::uint64_t maxAllocation = 0; ///< bytes of the largest single buffer
    std::uint64_t globalMemory = 0;  ///< bytes of all buffers together
    bool hostMemory = false;         ///< buffers take host memory (the process's limit holds)
};

/// Starts (and ends) the ledger of a context's buffers.
void trackContext(cl_context context, const MemoryLimits& limits);
void untrackContext(cl_context context);

/// Whether a buffer of `bytes` may replace one of `freed` bytes in `context`, and if so counts
/// it. Errors: Limit naming the bytes asked, the limit and what holds it. A context not tracked
/// admits everything.
Status admitBuffer(cl_context context, std::size_t bytes, std::size_t freed);
/// A buffer of `bytes` released.
void releaseBuffer(cl_context context, std::size_t bytes);

/// Where a buffer was reserved: the calling file and line, taken as a default argument
/// (`CallSite where = CallSite::here()`) the way std::source_location::current() is, which the
/// sanitizer build's clang with libstdc++ 12 does not provide.
struct CallSite {
    const char* file = "";
    unsigned line = 0;
    static constexpr CallSite here(const char* file = __builtin_FILE(),
                                   unsigned line = __builtin_LINE()) {
        return CallSite{file, line};
    }
};

/// A live buffer as the ledger lists it: where it was made and its size.
struct BufferRecord {
    std::string where;       ///< the reserving call, "file.cpp:line" under host/gpu
    std::uint64_t bytes = 0; ///< its size now
};

/// Names a buffer just made (`mem`, counted by admitBuffer) by the call that reserved it, and
/// drops the name of a buffer released. A context not tracked keeps no names.
void nameBuffer(cl_context context, cl_mem mem, std::size_t bytes, CallSite where);
void forgetBuffer(cl_context context, cl_mem mem);
/// The context's live buffers, the largest first (equal sizes by name).
std::vector<BufferRecord> deviceBuffers(cl_context context);

/// Bytes the context's buffers hold now, and at most so far.
std::uint64_t deviceBytesInUse(cl_context context);
std::uint64_t deviceBytesPeak(cl_context context);

} // namespace rubble::gpu
