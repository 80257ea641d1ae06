// host/gpu/particles.h: the particle method on the device (kernels/particles.cl, grid.cl): the
// particles moved with their bodies, the uniform grid by radix sort, the contacts between
// particles of different bodies, and (deterministic mode, or PGS) their stable order. The CPU
// twins of the same names are in host/collision/particles.cpp and grid.cpp.
#pragma once

#include <cstdint>
#include <span>

#include "host/collision/particles.h"
#include "host/gpu/pairs.h"
#include "host/gpu/sort.h"
#include "rubble/shared/particle.h"

namespace rubble::gpu {

/// The contacts of a step, their rows and per-body lists (the Jacobi family), and last step's
/// for warm starting. The count is known on the device; the host learns it when a step is met.
struct ContactBuffers {
    std::uint32_t capacity = 0;
    std::uint32_t count = 0;         ///< contacts of the last step met (or uploaded)
    std::uint32_t previousCount = 0; ///< contacts in `previous`, for warm starting
    Buffer contacts, previous, unsorted;
    Buffer rows, previousRows;
    Buffer impulses; ///< per row: its impulse on body b this sweep (rowImpulseItem)
    Buffer bodyCount, bodyStart, cursor, bodyList;
    Buffer arms;       ///< per list entry: the contact point from the body's centre of mass
    Buffer head, next; ///< last step's contacts chained per particle
    Buffer sortKeys, sortValues, sortKeysAlt, sortValuesAlt;
};

class ParticleCollision {
  public:
    /// Uploads the particles (null: none; contacts then come from uploadContacts) and sizes the
    /// grid and a first guess of the contacts. With `pairs` (PGS) each contact is also a pair
    /// of one point there, as many pairs as contacts. `capacity`: the first guess of the
    /// contacts (0: a few per particle). Errors: Device.
    Status create(StageQueue& q, const ParticleSet* set, BodiesView bodies, PairStore* pairs,
                  std::uint32_t capacity = 0);

    std::uint32_t count() const { return count_; }
    std::uint32_t cellBits() const { return bits_; }
    ContactBuffers& contacts() { return contacts_; }
    /// The particles' world positions (transform's output, buildGrid's input), the grid's
    /// sorted cell keys and particle order, and each cell's first sorted slot.
    Buffer& world() { return world_; }
    const Buffer& cellKeys() const { return keys_; }
    const Buffer& cellOrder() const { return values_; }
    const Buffer& cellFirst() const { return cellFirst_; }
    const ContactBuffers& contacts() const { return contacts_; }

    /// Each particle's world position from its body's pose (asleep bodies' stay).
    Status transform(StageQueue& q, const DeviceBodies& b);
    /// Cell keys, the radix sort, the cell ranges and the sorted copies of the particles.
    Status buildGrid(StageQueue& q, const DeviceBodies& b, RadixSort& sort);
    /// Contacts into the contact buffer, counted in the status block (may exceed the capacity).
    Status collide(StageQueue& q);
    /// Waits for the contact count into contacts().count; an overflow grows the buffers and
    /// collides again. Errors: Limit, Device.
    Status readCount(StageQueue& q);
    /// Contacts ordered by a stable sort on their particle; `byPair` (PGS) then by their pair
    /// (lower, higher body), the CPU's order of its manifolds.
    Status sortContacts(StageQueue& q, RadixSort& sort, std::uint32_t bodies, bool byPair);
    /// PGS, after sortContacts(byPair): each contact a pair of one point, last step's same
    /// contact found by key.
    Status toPairs(StageQueue& q, PairStore& pairs);

    /// Sizes the contact buffers (and the pairs' with PGS) for `capacity` contacts.
    Status setCapacity(StageQueue& q, std::uint32_t capacity);
    /// After an overflow (`st`): the buffers grown within the particles' budget, said on stderr
    /// (`again`: what runs again), and the status block's count and capacity set for the stages
    /// to run again. Errors: Limit past the budget (`step` named), Device.
    Status grow(StageQueue& q, const DeviceStatus& st, std::int64_t step, const char* again);
    /// This step's contacts and rows become the next step's warm start (`undo`: put back).
    Status keepForWarmStart(StageQueue& q);
    void undoKeep();
    /// Replaces this step's contacts (twin tests feed both paths the same set). Errors: Device.
    Status uploadContacts(StageQueue& q, std::span<const shared::ParticleContact> contacts);

  private:
    PairStore* pairs_ = nullptr;
    std::uint32_t count_ = 0, staticCount_ = 0, bits_ = 0;
    float cellSize_ = 0; ///< m
    float margin_ = 0;   ///< m: ParticleSet::margin
    Buffer records_, statics_, world_;
    Buffer keys_, values_, keysAlt_, valuesAlt_; ///< sorted cell keys and particles
    Buffer cellFirst_; ///< per cell and one more: the first sorted slot of a key >= the cell's
    Buffer sortedWorld_, sortedTags_; ///< positions and bodyTagItem in sorted order
    ContactBuffers contacts_;
    bool kept_ = false; ///< keepForWarmStart swapped the buffers this step
};

} // namespace rubble::gpu
