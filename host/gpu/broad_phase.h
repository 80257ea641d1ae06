// host/gpu/broad_phase.h: the SAT method's broad phase on the device (kernels/broad_phase.cl):
// each body's box grown by the margin and its reach this step, then candidate pairs by sweep and
// prune in grid columns, sorted by (a, b). The CPU twin is SatCollision::broadPhase.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/collision/contact.h"
#include "host/geometry/shape.h"
#include "host/gpu/pairs.h"
#include "host/gpu/sat.h"
#include "host/gpu/sort.h"
#include "rubble/shared/broad_phase.h"

namespace rubble::gpu {

class SatBroadPhase {
  public:
    /// The planes among the bodies (by their shapes), the joined pairs (which do not collide),
    /// the per-body boxes and the grid. Errors: Device.
    Status create(StageQueue& q, BodiesView bodies, std::span<const Shape> shapes,
                  std::span<const BodyPair> joined);
    /// computeAabbs then findPairs: the candidate pairs into `pairs.current`, their count in
    /// the status block (RUBBLE_STATUS_PAIRS, may exceed the capacity: nothing past it is kept).
    Status run(StageQueue& q, const DeviceBodies& b, const DeviceShapes& shapes, PairStore& pairs,
               RadixSort& sort, float dt);
    /// Each body's box, its spin (the part of the reach due to turning) and flags.
    Status computeAabbs(StageQueue& q, const DeviceBodies& b, const DeviceShapes& shapes, float dt);
    /// The grid, the candidate pairs (no two inactive bodies, none joined), sorted by (a, b).
    Status findPairs(StageQueue& q, const DeviceBodies& b, PairStore& pairs, RadixSort& sort);

    const Buffer& spin() const { return spin_; }
    /// Each body's box this step (BodyBox), as the narrow phase queries level meshes with it.
    const Buffer& boxes() const { return boxes_; }
    std::uint32_t planeCount() const { return planeCount_; }
    /// Reads the bodies' boxes. Errors: Device.
    Result<std::vector<shared::BodyBox>> downloadBoxes(StageQueue& q, std::uint32_t bodies) const;

  private:
    std::uint32_t planeCount_ = 0, joinedCount_ = 0;
    std::uint32_t gridBits_ = 0;  ///< the columns' keys are below 2^gridBits
    std::uint32_t sweepBits_ = 0; ///< the sweep keys' bits, below the column's in an entry's key
    Buffer planes_;               ///< indices of the plane bodies
    Buffer joined_;               ///< joined body pairs (min, max), sorted
    Buffer boxes_;                ///< BodyBox (a plane body: its world plane in min)
    Buffer spin_;                 ///< the part of the reach due to turning, m
    Buffer broadFlags_;           ///< RUBBLE_BROAD_*
    Buffer partials_, grid_;
    Buffer keys_, values_, keysAlt_, valuesAlt_; ///< (cell, body) entries, 4 per body at most
    Buffer cellBoxes_;                           ///< each sorted entry's box
    Buffer large_;                               ///< bodies too large for the grid
    Buffer bodyCount_, bodyStart_, cursor_;      ///< the pairs counted and placed per body
};

} // namespace rubble::gpu
