// host/gpu/traffic.h: the bytes each kernel of the device step moves per launch, counted from
// its reads and writes (each array element it touches once), so that a kernel's device time
// gives its achieved bandwidth; and the measured copy bandwidths of a device and of the host.
#pragma once

#include <cstdint>

#include "host/gpu/kernel_table.h"
#include "rubble/error.h"
#include "rubble/shared/constants.h"

namespace rubble::gpu {

class Context;

/// The sizes a step's kernels work on.
struct TrafficCounts {
    std::uint64_t bodies = 0;
    std::uint64_t particles = 0;
    std::uint64_t cells = 0;                     ///< of the particle grid (2^bits)
    std::uint64_t contacts = 0;                  ///< this step's
    std::uint64_t previous = 0;                  ///< last step's contacts (warm start)
    std::uint64_t sortItems = RUBBLE_SORT_ITEMS; ///< work-items of a sort pass (WorkSizes)
    std::uint64_t pairs = 0;                     ///< SAT: this step's body pairs
    std::uint64_t gridEntries = 0; ///< SAT: (cell, body) entries of the broad phase's grid
    std::uint64_t largeBodies = 0; ///< SAT: bodies tested against all
    std::uint64_t planes = 0;      ///< SAT: plane bodies
    std::uint64_t kept = 0;        ///< SAT: last step's kept pair entries (pairs and carried ones)
    std::uint64_t carried = 0;     ///< SAT: still pairs carried into this step's set
    std::uint64_t joints = 0;      ///< SAT: joints
    std::uint64_t jointBodies = 0; ///< SAT: bodies with a joint
    /// SAT: the joint groups projected as one, their members (joints), rows, and the entries of
    /// their matrices, each of jointReal bytes (WorkSizes::jointRealBytes).
    std::uint64_t directGroups = 0, directMembers = 0, directRows = 0, directMatrix = 0;
    std::uint64_t jointReal = 4;
};

/// Bytes one launch of `id` reads and writes, each element it touches counted once: a record
/// read whole counts its size, a field read alone its own; a body list entry per contact side;
/// neighbours that collideParticles reads again (they are in cache) are not counted again.
/// Kernels whose traffic depends on a size the counts do not hold (exclusiveScan, the dense
/// solver, explosions, obstacles) give 0: their dispatch records its own bytes.
std::uint64_t kernelBytes(KernelId id, const TrafficCounts& n);

/// Measured copy bandwidths, bytes per second (medians of repeated copies).
struct Bandwidth {
    std::uint64_t bytes = 0; ///< size of each copy
    double deviceCopy = 0;   ///< clEnqueueCopyBuffer, device to device (read + write counted)
    double hostToDevice = 0; ///< clEnqueueWriteBuffer from host memory
    double deviceToHost = 0; ///< clEnqueueReadBuffer into host memory
    double hostMemcpy = 0;   ///< std::memcpy on the host (read + write counted)
};

/// Copies buffers of `bytes` `repeats` times each way and takes the median time of each kind;
/// a device copy counts its bytes twice (read and written), as a kernel's bytes do; so does
/// memcpy. Errors: Device.
Result<Bandwidth> measureBandwidth(const Context& c, std::uint64_t bytes, int repeats);

} // namespace rubble::gpu
