// kernels/particles.cl: entry points of OpenCL stages 2 and 4 (transformParticles,
// collideParticles, and particlePairs for projected Gauss-Seidel); the math is in
// rubble/shared/particle.h, the CPU twins in host/collision/particles.cpp.
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/particle.h"

// Particles of sleeping bodies keep their world positions: their bodies do not move.
__kernel void transformParticles(const uint count, __global const Particle* particles,
                                 __global const BodyPose* poses, __global const uint* flags,
                                 __global float4* world) {
    const uint i = get_global_id(0);
    if (i >= count) return; // the global size is rounded up to the group size
    const Particle p = particles[i];
    if (flags[p.body] & RUBBLE_BODY_ASLEEP) return;
    world[i] = transformParticleItem(p, poses[p.body]);
}

// Appends a contact; past the capacity it only counts, and the host grows the buffer.
static void appendContact(ParticleContact c, const uint capacity,
                          __global ParticleContact* contacts, __global uint* status) {
    const uint at = atomic_inc(&status[RUBBLE_STATUS_CONTACTS]);
    if (at < capacity) contacts[at] = c;
    // A gap is no penetration (and a negative float's bits would read as the largest).
    atomic_max(&status[RUBBLE_STATUS_PENETRATION], as_uint(fmax(c.point.w, 0.0f)));
}

// The contact of the particles in sorted slots `slot` (body a) and `other` (body b), if they
// are closer than the margin.
static void touchParticles(const float4 xi, const float4 xj, const uint slot, const uint other,
                           const uint a, const uint b, const float margin,
                           __global const uint* order, const uint capacity,
                           __global ParticleContact* contacts, __global uint* status) {
    ParticleContact c = particlePairItem(xi, xj);
    if (!particleContactMadeItem(c.point.w, margin)) return;
    c.a = a;
    c.b = b;
    c.particleA = order[slot];
    c.featureB = order[other];
    appendContact(c, capacity, contacts, status);
}

// One work-item per sorted slot: a particle of a body that tests pairs against the other bodies'
// particles in the 27 neighbouring cells (distinct keys: see cellHashItem), then, for an active
// body, against the static shapes. Which side tests a pair: pairFromHereItem. The grid's sorted
// copies (sortedWorld, sortedTags) keep a cell's particles together, and the three cells of a
// row in x are consecutive keys unless the row wraps: their particles are then one run of slots,
// from cellFirst of the row's first cell to cellFirst of the cell after its last.
__kernel void collideParticles(const uint count, const uint staticCount,
                               const float inverseCellSize, const uint bits, const float margin,
                               __global const uint* cellFirst, __global const float4* sortedWorld,
                               __global const uint* sortedTags, __global const uint* order,
                               __global const StaticShape* statics,
                               __global ParticleContact* contacts, __global uint* status) {
    const uint slot = get_global_id(0);
    if (slot >= count) return;
    const uint tagI = sortedTags[slot];
    const uint bodyI = tagBodyItem(tagI), flagsI = tagFlagsItem(tagI);
    if (!testsPairsItem(flagsI)) return;
    const uint capacity = status[RUBBLE_STATUS_CAPACITY];
    const float4 xi = sortedWorld[slot];
    const int cx = cellCoordinate(xi.x, inverseCellSize),
              cy = cellCoordinate(xi.y, inverseCellSize),
              cz = cellCoordinate(xi.z, inverseCellSize);
    const uint xMask = (1u << cellBitsXItem(bits)) - 1u;
    const int wraps = ((uint)(cx - 1) & xMask) > ((uint)(cx + 1) & xMask);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
            for (int dx = -1; dx <= 1; ++dx) {
                // A row that does not wrap is one run of slots, read once, from dx = -1; a row
                // that wraps is read cell by cell.
                const uint key = cellHashItem(cx + dx, cy + dy, cz + dz, bits);
                const uint begin = cellFirst[key], end = cellFirst[key + (wraps ? 1u : 3u)];
                if (!wraps) dx = 1;
                // Particles sorted before this one: only those that test nothing themselves
                // (static, kinematic, asleep) pair from here, and their flags say so first.
                for (uint s = begin; s < min(end, slot); ++s) {
                    const uint tagJ = sortedTags[s];
                    const uint bodyJ = tagBodyItem(tagJ);
                    if (!pairFromHereItem(bodyI, flagsI, bodyJ, tagFlagsItem(tagJ), 0)) continue;
                    const float4 xj = sortedWorld[s];
                    if (!particlesMayTouchItem(xi, xj, margin)) continue;
                    touchParticles(xi, xj, slot, s, bodyI, bodyJ, margin, order, capacity, contacts,
                                   status);
                }
                // Particles sorted after it: most are out of reach, which the distance says.
                for (uint s = max(begin, slot + 1); s < end; ++s) {
                    const float4 xj = sortedWorld[s];
                    if (!particlesMayTouchItem(xi, xj, margin)) continue;
                    const uint tagJ = sortedTags[s];
                    const uint bodyJ = tagBodyItem(tagJ);
                    const uint flagsJ = tagFlagsItem(tagJ);
                    if (!pairFromHereItem(bodyI, flagsI, bodyJ, flagsJ, 1)) continue;
                    // Two active bodies meet in the order of their indices, whichever particle
                    // found the pair: the contact keeps its key (warm start) from step to step.
                    if (activeBodyItem(flagsJ) && bodyJ < bodyI)
                        touchParticles(xj, xi, s, slot, bodyJ, bodyI, margin, order, capacity,
                                       contacts, status);
                    else
                        touchParticles(xi, xj, slot, s, bodyI, bodyJ, margin, order, capacity,
                                       contacts, status);
                }
            }
    if (!activeBodyItem(flagsI)) return;
    for (uint k = 0; k < staticCount; ++k) {
        ParticleContact c = particleStaticItem(xi, statics[k]);
        if (!particleContactMadeItem(c.point.w, margin)) continue;
        c.a = bodyI;
        c.particleA = order[slot];
        c.featureB = count + k;
        appendContact(c, capacity, contacts, status);
    }
}

// Particle contacts into projected Gauss-Seidel (solver pgs), one work-item per contact
// (striding), after the contacts' sort by (pair, particleA, featureB): each contact becomes a
// pair of one point in the pair arrays the SAT method's narrow phase fills (particleManifoldItem,
// as the CPU's particleContactsToManifolds), with its key, and last step's place of the same
// contact (`previousOf`; last step's count when it is new), from which the rows warm-start. The
// pairs' count is the contacts'.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_CONTACTS, 1, 1))) void
particlePairs(__global uint* status, __global const ParticleContact* contacts,
              const uint previousCapacity, __global const uint* previousCount,
              __global const ParticleContactKey* previousKeys, __global uint* pairCount,
              __global BodyPairRecord* pairs, __global ContactManifold* manifolds,
              __global ParticleContactKey* keys, __global uint* previousOf) {
    const uint n = liveContactsItem(status[RUBBLE_STATUS_CONTACTS], status[RUBBLE_STATUS_CAPACITY]);
    const uint previous = min(previousCount[0], previousCapacity);
    if (get_global_id(0) == 0u) {
        pairCount[0] = n;
        status[RUBBLE_STATUS_PAIRS] = n;
    }
    for (uint i = get_global_id(0); i < n; i += get_global_size(0)) {
        const ParticleContact c = contacts[i];
        const ContactManifold m = particleManifoldItem(c);
        BodyPairRecord pair;
        pair.a = m.a;
        pair.b = m.b;
        pairs[i] = pair;
        manifolds[i] = m;
        const ParticleContactKey key = particleContactKeyItem(c);
        keys[i] = key;
        // Where the contact would be among last step's if the two were spread alike.
        const uint hint = (uint)(((ulong)i * previous) / n);
        previousOf[i] = findParticleKeyItem(key, hint, previous, previousKeys);
    }
}
