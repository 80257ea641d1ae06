// include/rubble/shared/particle.h: particle records, the static world, and the per-element math
// of OpenCL stages 2 to 4 (transformParticles, buildGrid, collideParticles). CPU twins are in
// host/collision/particle_*.cpp; kernels in kernels/particles.cl and kernels/grid.cl.
#pragma once

#include "rubble/shared/body.h"
#include "rubble/shared/clip.h"
#include "rubble/shared/constants.h"

RUBBLE_SHARED_BEGIN

// 32 bytes, made once at load by voxelising the body's shape.
typedef struct Particle {
    float4 offset;         // from the body's centre of mass, body frame, m (w = radius, m)
    uint body;             // index into the body arrays
    uint pad0, pad1, pad2; // keeps the 16-byte stride
} Particle;
RUBBLE_STATIC_ASSERT_SIZE(Particle, 32);

// Kinds of static shape that particles meet analytically.
#define RUBBLE_STATIC_PLANE 0u
#define RUBBLE_STATIC_BOX 1u

// 80 bytes: one piece of the static world. A plane's solid side is below
// dot(normal, x) = normal.w; a box is its centre, orientation and half extents.
typedef struct StaticShape {
    float4 normal;      // plane: unit, out of the solid, world (w = offset, m)
    float4 position;    // box: centre, world, m
    float4 orientation; // box: unit quaternion (x, y, z, w), box to world
    float4 halfExtents; // box: m
    uint kind;          // RUBBLE_STATIC_PLANE or RUBBLE_STATIC_BOX
    float friction;     // Coulomb coefficient of its material
    float restitution;  // of its material
    uint body;          // the static body it belongs to
} StaticShape;
RUBBLE_STATIC_ASSERT_SIZE(StaticShape, 80);

// 48 bytes: a particle touching another body's particle or the static world.
typedef struct ParticleContact {
    float4 point;   // midway between the two surfaces, world, m (w = depth: penetration, m)
    float4 normal;  // unit, world, from body a to body b (w = 0)
    uint a, b;      // body indices: a found it (active, or a moving kinematic body meeting a
                    // sleeping b); b may be static, kinematic or asleep (the static body for the
                    // static world)
    uint particleA; // a's particle: rows are sorted by it in deterministic mode
    uint featureB;  // b's particle, or particle count + static shape index
} ParticleContact;
RUBBLE_STATIC_ASSERT_SIZE(ParticleContact, 48);

// A particle contact's feature id: its two particles name it while they keep touching, so that
// projected Gauss-Seidel warm-starts it (particleContactsToManifolds, particlePairs).
RUBBLE_FN uint particleFeatureItem(uint particleA, uint featureB) {
    return particleA * 2654435761u ^ featureB;
}

// A particle contact as the manifold of one point that projected Gauss-Seidel takes, between
// bodies min(a, b) and max(a, b), its normal from the first to the second (the CPU's
// particleContactsToManifolds).
RUBBLE_FN ContactManifold particleManifoldItem(ParticleContact c) {
    const int swap = c.a > c.b;
    ContactManifold m = emptyContactsItem();
    m.a = swap ? c.b : c.a;
    m.b = swap ? c.a : c.b;
    m.normal = swap ? vec4(-c.normal.x, -c.normal.y, -c.normal.z)
                    : vec4(c.normal.x, c.normal.y, c.normal.z);
    m.points[0] = c.point;
    m.features[0] = particleFeatureItem(c.particleA, c.featureB);
    m.count = 1u;
    return m;
}

// 16 bytes: what names a particle contact from step to step, in the order projected
// Gauss-Seidel takes the contacts: its pair (lower, higher body), then its particles.
typedef struct ParticleContactKey {
    uint lower, higher; // min(a, b), max(a, b)
    uint particleA, featureB;
} ParticleContactKey;
RUBBLE_STATIC_ASSERT_SIZE(ParticleContactKey, 16);

RUBBLE_FN ParticleContactKey particleContactKeyItem(ParticleContact c) {
    ParticleContactKey k;
    k.lower = c.a < c.b ? c.a : c.b;
    k.higher = c.a < c.b ? c.b : c.a;
    k.particleA = c.particleA;
    k.featureB = c.featureB;
    return k;
}

RUBBLE_FN int particleKeyLessItem(ParticleContactKey x, ParticleContactKey y) {
    if (x.lower != y.lower) return x.lower < y.lower;
    if (x.higher != y.higher) return x.higher < y.higher;
    if (x.particleA != y.particleA) return x.particleA < y.particleA;
    return x.featureB < y.featureB;
}

// The index of `key` among `count` keys in that order, or `count` when it is not among them:
// last step's place of a contact, whose impulses warm-start it. The search starts at `hint`
// (where the key would be if the two steps' contacts were spread alike): it gallops away from
// the hint in strides that double until it passes the key, then halves the last stride. Last
// step's place is seldom far from the hint, so that a search reads a few keys near it where a
// binary search over all of them reads one in each of log2(count) places far apart.
RUBBLE_FN uint findParticleKeyItem(ParticleContactKey key, uint hint, uint count,
                                   RUBBLE_GLOBAL const ParticleContactKey* keys) {
    if (count == 0u) return 0u;
    hint = hint < count ? hint : count - 1u;
    // [lo, hi): where the first key not below `key` is, if not at hi.
    uint lo, hi;
    uint stride = 1u;
    if (particleKeyLessItem(keys[hint], key)) {
        lo = hint + 1u;
        hi = count;
        while (lo + stride - 1u < count && particleKeyLessItem(keys[lo + stride - 1u], key)) {
            lo += stride;
            stride *= 2u;
        }
        if (lo + stride - 1u < count) hi = lo + stride - 1u;
    } else {
        hi = hint;
        lo = 0u;
        while (hi >= stride && !particleKeyLessItem(keys[hi - stride], key)) {
            hi -= stride;
            stride *= 2u;
        }
        if (hi >= stride) lo = hi - stride + 1u;
    }
    while (lo < hi) {
        const uint mid = lo + (hi - lo) / 2u;
        if (particleKeyLessItem(keys[mid], key))
            lo = mid + 1u;
        else
            hi = mid;
    }
    return lo < count && !particleKeyLessItem(key, keys[lo]) ? lo : count;
}

// world position = x + q offset q^-1, with w the particle's radius.
RUBBLE_FN float4 transformParticleItem(Particle p, BodyPose pose) {
    const float4 x = add4(pose.position, quatRotate(pose.orientation, p.offset));
    return make4(x.x, x.y, x.z, p.offset.w);
}

// The integer cell of a world point on a grid of the given cell size (m).
RUBBLE_FN int cellCoordinate(float x, float inverseCellSize) {
    return (int)floor(x * inverseCellSize);
}

// Cell (x, y, z) on a grid that wraps around every 2^bx cells in x, 2^bz in z and 2^by in y
// (bits = bx + bz + by, each at least 3): neighbouring cells in x are neighbours in the table,
// so that the 27 cells around a particle are 9 short runs of memory (a hash with large primes
// scatters them and the stage waits on cache misses), and the 27 keys are distinct. Cells
// that alias across the wrap only add candidates that the distance test rejects.
RUBBLE_FN uint cellBitsXItem(uint bits) {
    const uint by = bits / 3u, bz = (bits - by) / 2u;
    return bits - by - bz;
}
RUBBLE_FN uint cellHashItem(int x, int y, int z, uint bits) {
    const uint by = bits / 3u, bz = (bits - by) / 2u, bx = bits - by - bz;
    const uint ux = (uint)x & ((1u << bx) - 1u), uz = (uint)z & ((1u << bz) - 1u),
               uy = (uint)y & ((1u << by) - 1u);
    return ux | (uz << bx) | (uy << (bx + bz));
}

// True when `key` is not among the first n keys already visited (the CPU twin asserts that
// the 27 neighbour keys are distinct).
RUBBLE_FN int neighbourCellIsNewItem(const uint* seen, uint n, uint key) {
    for (uint i = 0; i < n; ++i)
        if (seen[i] == key) return 0;
    return 1;
}

// The grid key of a particle's world position (w ignored).
RUBBLE_FN uint cellKeyItem(float4 x, float inverseCellSize, uint bits) {
    return cellHashItem(cellCoordinate(x.x, inverseCellSize), cellCoordinate(x.y, inverseCellSize),
                        cellCoordinate(x.z, inverseCellSize), bits);
}

// The field of a pass of the contacts' sort (kernels/grid.cl, contactKeys).
#define RUBBLE_CONTACT_KEY_FEATURE 0u
#define RUBBLE_CONTACT_KEY_PARTICLE 1u
#define RUBBLE_CONTACT_KEY_HIGHER 2u
#define RUBBLE_CONTACT_KEY_LOWER 3u

// The contacts the stages after collideParticles work on: all that were appended, or none when
// they overflowed the buffer (the host grows it and runs those stages again).
RUBBLE_FN uint liveContactsItem(uint appended, uint capacity) {
    return appended <= capacity ? appended : 0u;
}

// The grid's sorted copy of a particle's body: its index in the low 27 bits and its flags
// (RUBBLE_BODY_*, five bits) above, so that collision reads one word per candidate.
#define RUBBLE_TAG_BODY_BITS 27u
#define RUBBLE_TAG_MAX_BODIES (1u << RUBBLE_TAG_BODY_BITS)
RUBBLE_FN uint bodyTagItem(uint body, uint flags) { return body | (flags << RUBBLE_TAG_BODY_BITS); }
RUBBLE_FN uint tagBodyItem(uint tag) { return tag & (RUBBLE_TAG_MAX_BODIES - 1u); }
RUBBLE_FN uint tagFlagsItem(uint tag) { return tag >> RUBBLE_TAG_BODY_BITS; }

// A cheap test before particlePairItem: false only when the two particles (xyz world, w
// radius) are certainly apart by more than `margin` (m) (their squared distance beyond the
// squared reach, with room for the round-off of the exact test).
RUBBLE_FN int particlesMayTouchItem(float4 xa, float4 xb, float margin) {
    const float dx = xb.x - xa.x, dy = xb.y - xa.y, dz = xb.z - xa.z;
    const float reach = xa.w + xb.w + margin;
    return dx * dx + dy * dy + dz * dz <= reach * reach * 1.0001f;
}

// Whether a particle contact of this depth (m; negative: a gap) is made: overlapping, or for
// projected Gauss-Seidel less than the speculative margin (m) apart; the Jacobi solvers' margin
// is 0, their rows pushing apart only what overlaps.
RUBBLE_FN int particleContactMadeItem(float depth, float margin) { return depth > -margin; }

// Bodies whose particles start collision tests: active ones, and kinematic ones that move
// (they meet sleeping bodies, to wake them).
RUBBLE_FN int testsPairsItem(uint flags) {
    return activeBodyItem(flags) || (flags & RUBBLE_BODY_WAKING) != 0u;
}

// Whether a particle of body `self` tests a pair with a particle of body `other` that comes
// after it in the grid's sorted order (`later`) or before it: never its own body or an absent
// one; an active body tests another active one when that one comes later (the pair once) and
// every static, kinematic or sleeping one (those test nothing themselves), so that body a of a
// contact is active; a moving kinematic body tests sleeping ones only.
RUBBLE_FN int pairFromHereItem(uint self, uint selfFlags, uint other, uint otherFlags,
                               int later) {
    if (other == self || (otherFlags & RUBBLE_BODY_ABSENT)) return 0;
    if (activeBodyItem(selfFlags)) return !activeBodyItem(otherFlags) || later;
    return (otherFlags & RUBBLE_BODY_ASLEEP) != 0u;
}

// Two particles (xyz world, w radius): depth in point.w (> 0 overlapping, < 0 the gap between
// their surfaces), normal from a to b; depth 0 when they are at the same point.
RUBBLE_FN ParticleContact particlePairItem(float4 xa, float4 xb) {
    ParticleContact c;
    const float4 d = vec4(xb.x - xa.x, xb.y - xa.y, xb.z - xa.z);
    const float dist = length3(d);
    const float depth = xa.w + xb.w - dist;
    c.normal = dist > 0.0f ? scale4(d, 1.0f / dist) : vec4(0.0f, 1.0f, 0.0f);
    // The point halfway between the two sphere surfaces along the normal.
    const float4 pa = add4(vec4(xa.x, xa.y, xa.z), scale4(c.normal, xa.w - 0.5f * depth));
    c.point = make4(pa.x, pa.y, pa.z, dist > 0.0f ? depth : 0.0f);
    c.a = 0u;
    c.b = 0u;
    c.particleA = 0u;
    c.featureB = 0u;
    return c;
}

// A particle (xyz world, w radius) against a static shape: depth in point.w (<= 0: apart),
// normal from the particle's body into the static shape.
RUBBLE_FN ParticleContact particleStaticItem(float4 x, StaticShape s) {
    ParticleContact c;
    const float4 p = vec4(x.x, x.y, x.z);
    c.a = 0u;
    c.b = s.body;
    c.particleA = 0u;
    c.featureB = 0u;
    if (s.kind == RUBBLE_STATIC_PLANE) {
        const float4 n = vec4(s.normal.x, s.normal.y, s.normal.z);
        const float height = dot3(n, p) - s.normal.w; // centre above the surface, m
        const float depth = x.w - height;
        c.normal = scale4(n, -1.0f);
        const float4 onSurface = sub4(p, scale4(n, height));
        const float4 mid = sub4(onSurface, scale4(n, 0.5f * depth));
        c.point = make4(mid.x, mid.y, mid.z, depth);
        return c;
    }
    // Box: the closest point of the box to the centre, in the box frame.
    const float4 inBox = quatRotateInverse(s.orientation, sub4(p, s.position));
    const float4 h = s.halfExtents;
    const float4 q = vec4(fmin(fmax(inBox.x, -h.x), h.x), fmin(fmax(inBox.y, -h.y), h.y),
                          fmin(fmax(inBox.z, -h.z), h.z));
    const float4 d = sub4(inBox, q);
    const float dist = length3(d);
    float4 nLocal;
    float depth;
    float4 surfaceLocal = q; // where the box's surface meets the normal, box frame
    if (dist > 0.0f) {
        // Centre outside the box: push along the line to the closest point.
        nLocal = scale4(d, 1.0f / dist);
        depth = x.w - dist;
    } else {
        // Centre inside: leave through the nearest face.
        const float ex = h.x - fabs(inBox.x), ey = h.y - fabs(inBox.y), ez = h.z - fabs(inBox.z);
        if (ex <= ey && ex <= ez) {
            nLocal = vec4(inBox.x < 0.0f ? -1.0f : 1.0f, 0.0f, 0.0f);
            depth = x.w + ex;
        } else if (ey <= ez) {
            nLocal = vec4(0.0f, inBox.y < 0.0f ? -1.0f : 1.0f, 0.0f);
            depth = x.w + ey;
        } else {
            nLocal = vec4(0.0f, 0.0f, inBox.z < 0.0f ? -1.0f : 1.0f);
            depth = x.w + ez;
        }
    }
    if (dist <= 0.0f) surfaceLocal = add4(inBox, scale4(nLocal, depth - x.w));
    // nLocal points out of the box; the contact normal points into it. The point is halfway
    // between the box's surface and the particle's deepest point.
    const float4 n = quatRotate(s.orientation, nLocal);
    c.normal = scale4(n, -1.0f);
    const float4 onSurface = add4(s.position, quatRotate(s.orientation, surfaceLocal));
    const float4 mid = sub4(onSurface, scale4(n, 0.5f * depth));
    c.point = make4(mid.x, mid.y, mid.z, depth);
    return c;
}

RUBBLE_SHARED_END
