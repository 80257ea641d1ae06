// kernels/particles.cl: entry points of OpenCL stages 2 and 4 (transformParticles,
// collideParticles); the math is in rubble/shared/particle.h, the CPU twins in
// host/collision/particle_world.cpp.
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
    atomic_max(&status[RUBBLE_STATUS_PENETRATION], as_uint(c.point.w));
}

// One work-item per sorted slot: a particle of a body that tests pairs against the other bodies'
// particles in the 27 neighbouring cells (distinct keys: see cellHashItem), then, for an active
// body, against the static shapes. The grid's sorted copies (sortedWorld, sortedBody) keep a
// cell's particles together in memory. Which side tests a pair: pairFromHereItem.
__kernel void collideParticles(const uint count, const uint staticCount,
                               const float inverseCellSize, const uint bits,
                               __global const uint* cellStart, __global const uint* cellEnd,
                               __global const float4* sortedWorld,
                               __global const uint* sortedBody, __global const uint* order,
                               __global const uint* flags, __global const StaticShape* statics,
                               __global ParticleContact* contacts, __global uint* status) {
    const uint slot = get_global_id(0);
    if (slot >= count) return;
    const uint bodyI = sortedBody[slot];
    const uint flagsI = flags[bodyI];
    if (!testsPairsItem(flagsI)) return;
    const uint capacity = status[RUBBLE_STATUS_CAPACITY];
    const float4 xi = sortedWorld[slot];
    const int cx = cellCoordinate(xi.x, inverseCellSize), cy = cellCoordinate(xi.y, inverseCellSize),
              cz = cellCoordinate(xi.z, inverseCellSize);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
            for (int dx = -1; dx <= 1; ++dx) {
                const uint key = cellHashItem(cx + dx, cy + dy, cz + dz, bits);
                const uint start = cellStart[key];
                if (start == RUBBLE_EMPTY_CELL) continue;
                const uint end = cellEnd[key];
                for (uint s = start; s < end; ++s) {
                    const uint bodyJ = sortedBody[s];
                    if (!pairFromHereItem(bodyI, flagsI, bodyJ, flags[bodyJ])) continue;
                    ParticleContact c = particlePairItem(xi, sortedWorld[s]);
                    if (!(c.point.w > 0.0f)) continue;
                    c.a = bodyI;
                    c.b = bodyJ;
                    c.particleA = order[slot];
                    c.featureB = order[s];
                    appendContact(c, capacity, contacts, status);
                }
            }
    if (!activeBodyItem(flagsI)) return;
    for (uint k = 0; k < staticCount; ++k) {
        ParticleContact c = particleStaticItem(xi, statics[k]);
        if (!(c.point.w > 0.0f)) continue;
        c.a = bodyI;
        c.particleA = order[slot];
        c.featureB = count + k;
        appendContact(c, capacity, contacts, status);
    }
}
