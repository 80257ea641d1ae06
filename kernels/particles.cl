// kernels/particles.cl: entry points of OpenCL stages 2 and 4 (transformParticles,
// collideParticles); the math is in rubble/shared/particle.h, the CPU twins in
// host/collision/particle_world.cpp.
#include "rubble/shared/particle.h"

__kernel void transformParticles(const uint count, __global const Particle* particles,
                                 __global const BodyPose* poses, __global float4* world) {
    const uint i = get_global_id(0);
    if (i >= count) return; // the global size is rounded up to the group size
    const Particle p = particles[i];
    world[i] = transformParticleItem(p, poses[p.body]);
}

// Appends a contact; past the capacity it only counts, and the host grows the buffer.
static void appendContact(ParticleContact c, const uint capacity,
                          __global ParticleContact* contacts, __global uint* status) {
    const uint at = atomic_inc(&status[RUBBLE_STATUS_CONTACTS]);
    if (at < capacity) contacts[at] = c;
    atomic_max(&status[RUBBLE_STATUS_PENETRATION], as_uint(c.point.w));
}

// One work-item per sorted slot: its particle against the other bodies' particles in the 27
// neighbouring cells (distinct keys: see cellHashItem) (a pair once, from the lower body) and against the static shapes.
__kernel void collideParticles(const uint count, const uint staticCount,
                               const float inverseCellSize, const uint bits, const uint capacity,
                               __global const uint* order, __global const uint* cellStart,
                               __global const uint* cellEnd, __global const float4* world,
                               __global const Particle* particles,
                               __global const BodyMass* masses,
                               __global const StaticShape* statics,
                               __global ParticleContact* contacts, __global uint* status) {
    const uint slot = get_global_id(0);
    if (slot >= count) return;
    const uint i = order[slot];
    const float4 xi = world[i];
    const uint bodyI = particles[i].body;
    const int staticI = masses[bodyI].inverseMass == 0.0f;
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
                    const uint j = order[s];
                    const uint bodyJ = particles[j].body;
                    if (bodyJ <= bodyI) continue;
                    if (staticI && masses[bodyJ].inverseMass == 0.0f) continue;
                    ParticleContact c = particlePairItem(xi, world[j]);
                    if (!(c.point.w > 0.0f)) continue;
                    c.a = bodyI;
                    c.b = bodyJ;
                    c.particleA = i;
                    c.featureB = j;
                    appendContact(c, capacity, contacts, status);
                }
            }
    if (staticI) return;
    for (uint k = 0; k < staticCount; ++k) {
        ParticleContact c = particleStaticItem(xi, statics[k]);
        if (!(c.point.w > 0.0f)) continue;
        c.a = bodyI;
        c.particleA = i;
        c.featureB = count + k;
        appendContact(c, capacity, contacts, status);
    }
}
