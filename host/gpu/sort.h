// host/gpu/sort.h: the device's radix sort of (key, value) pairs and its exclusive scan
// (kernels/grid.cl), shared by the particle grid, the broad phase and the contact order.
#pragma once

#include <cstdint>

#include "host/gpu/stage_queue.h"

namespace rubble::gpu {

/// out[i] = sum of in[0..i-1] for i <= count, on one work-item (enqueued).
Status exclusiveScan(StageQueue& q, const Buffer& in, const Buffer& out, std::uint32_t count);

/// A stable least-significant-digit radix sort with its histogram and offsets.
class RadixSort {
  public:
    /// Errors: Device.
    Status create(StageQueue& q);
    /// Sorts `count` (key, value) pairs by the low `bits` of the key, stably; the result is in
    /// keys and values (the Alt buffers are scratch, swapped). The count is the smaller of
    /// `count` and the status slot `countSlot` (RUBBLE_STATUS_COUNT: none), read on the device.
    Status sort(StageQueue& q, Buffer& keys, Buffer& values, Buffer& keysAlt, Buffer& valuesAlt,
                std::uint32_t count, std::uint32_t bits,
                std::uint32_t countSlot = RUBBLE_STATUS_COUNT);

  private:
    Buffer histogram_, offsets_;
};

} // namespace rubble::gpu
