// include/rubble/shared/broad_phase.h: the device broad phase's records and per-element math:
// world boxes grown by the margin and each body's reach this step, planes as the CPU pairs them
// (host/collision/sat_collision.cpp and broad_phase.cpp), and the columns the device sweeps for
// candidate pairs (kernels/broad_phase.cl), as the CPU's findPairs does.
#pragma once

#include "rubble/shared/clip.h"
#include "rubble/shared/hull.h"

RUBBLE_SHARED_BEGIN

// Broad-phase flags of a body (broadFlags), written by computeAabbs and gridEntries.
#define RUBBLE_BROAD_INACTIVE 1u // static or asleep: never paired with another inactive body
#define RUBBLE_BROAD_NO_BOX 2u   // not in the grid: a plane, a non-finite box, an absent body
#define RUBBLE_BROAD_LARGE 4u    // spans more than two cells on an axis: tested against all

// 32 bytes: an axis-aligned box, world frame, m (Aabb). w of min is 1 for an inactive body (the
// broad phase's flags, where the pair test reads them), else 0.
typedef struct BodyBox {
    float4 min;
    float4 max;
} BodyBox;
RUBBLE_STATIC_ASSERT_SIZE(BodyBox, 32);

// 8 bytes: two bodies whose boxes overlap, a < b (BodyPair).
typedef struct BodyPairRecord {
    uint a, b;
} BodyPairRecord;
RUBBLE_STATIC_ASSERT_SIZE(BodyPairRecord, 8);

// Where the pair (a, b) is, or would be, among `count` pairs sorted by (a, b), searched from
// index `from` on (every pair before it sorts before the pair): the first index from `from` whose
// pair does not sort before it (`count` when none), a binary search after a look at `from`
// itself, where a caller going through its own sorted pairs in order usually finds the next one.
RUBBLE_FN uint lowerPairItem(BodyPairRecord pair, uint from, uint count,
                             RUBBLE_GLOBAL const BodyPairRecord* pairs) {
    uint lo = from, hi = count;
    if (lo < hi && pairs[lo].a == pair.a && pairs[lo].b == pair.b) return lo;
    while (lo < hi) {
        const uint mid = lo + (hi - lo) / 2u;
        const BodyPairRecord p = pairs[mid];
        if (p.a < pair.a || (p.a == pair.a && p.b < pair.b))
            lo = mid + 1u;
        else
            hi = mid;
    }
    return lo;
}

// The index of the pair (a, b) among `count` pairs sorted by (a, b), or `count` when it is not
// among them, searched from `from` (lowerPairItem).
RUBBLE_FN uint findPairFromItem(BodyPairRecord pair, uint from, uint count,
                                RUBBLE_GLOBAL const BodyPairRecord* pairs) {
    const uint lo = lowerPairItem(pair, from, count, pairs);
    return lo < count && pairs[lo].a == pair.a && pairs[lo].b == pair.b ? lo : count;
}

// The entries a pair set keeps for the next step's lookups (its count's two words: the pairs
// found, then those and the still pairs carried after them), within its capacity. A set that
// carries nothing (particles with PGS) leaves the second word 0: its entries are its pairs.
RUBBLE_FN uint keptPairsItem(RUBBLE_GLOBAL const uint* count, uint capacity) {
    const uint found = count[0] < capacity ? count[0] : capacity;
    const uint kept = count[1] < capacity ? count[1] : capacity;
    return kept > found ? kept : found;
}

// ... searched from the first: as the device finds a joined pair.
RUBBLE_FN uint findPairItem(BodyPairRecord pair, uint count,
                            RUBBLE_GLOBAL const BodyPairRecord* pairs) {
    return findPairFromItem(pair, 0u, count, pairs);
}

// 64 bytes: the columns of one step, from the boxes' bounds and mean widths: a grid of cells over
// two axes, one cell along the third (the sweep axis, where the boxes spread most), along which
// a column's entries are sorted by their start.
typedef struct GridParams {
    float4 origin;      // lowest corner of the boxes, m
    float4 inverseCell; // 1 / cell width per axis, 1/m; on the sweep axis, sweep steps per m
    uint cells[4];      // cells per axis (x, y, z; 1 on the sweep axis); w: their product
    uint largeAbove;    // a body spanning more cells than this on an axis is large (2)
    uint sweepAxis;     // 0, 1 or 2
    uint sweepBits;     // the sweep key's bits, below the column's in an entry's key
    uint pad0;
} GridParams;
RUBBLE_STATIC_ASSERT_SIZE(GridParams, 64);

// 64 bytes: one work-item's part of the reduction behind GridParams.
typedef struct GridPartial {
    float4 lo, hi;   // bounds of its boxes, m
    float4 widthSum; // summed box widths per axis, m
    uint count;      // boxes summed
    uint pad0, pad1, pad2;
} GridPartial;
RUBBLE_STATIC_ASSERT_SIZE(GridPartial, 64);

// How far any point of the body moves this step, and the part due to turning (m): the
// reach (|v| + |w| r) dt of SatCollision::broadPhase.
RUBBLE_FN float spinItem(BodyVelocity v, float boundingRadius, float dt) {
    return sqrt(dot3(v.angular, v.angular)) * boundingRadius * dt;
}
RUBBLE_FN float reachItem(BodyVelocity v, float spin, float dt) {
    return sqrt(dot3(v.linear, v.linear)) * dt + spin;
}

// The margin of a pair: kContactMargin plus how much closer the two can come this step
// (pairReach).
RUBBLE_FN float pairMarginItem(BodyVelocity va, BodyVelocity vb, float spinA, float spinB,
                               float dt) {
    const float4 relative = sub4(vb.linear, va.linear);
    return RUBBLE_CONTACT_MARGIN + (sqrt(dot3(relative, relative)) * dt + spinA + spinB);
}

// The world box of a shape grown by margin (worldBox): a hull's local box turned (|R| times its
// half extents), a sphere's centre plus its radius.
RUBBLE_FN BodyBox worldBoxItem(HullShape shape, RigidTransform t, float margin) {
    BodyBox box;
    if (shape.kind == RUBBLE_SHAPE_SPHERE) {
        const float r = shape.radius + margin;
        const float4 e = vec4(r, r, r);
        box.min = sub4(t.translation, e);
        box.max = add4(t.translation, e);
        return box;
    }
    const float4 centre = transformApply(t, scale4(add4(shape.boundsMin, shape.boundsMax), 0.5f));
    const float4 halfSize = scale4(sub4(shape.boundsMax, shape.boundsMin), 0.5f);
    const Mat3 r = t.rotation;
    // Column by column, as glm adds |R[c]| half[c] to the margin.
    float4 extent = vec4(margin, margin, margin);
    extent = add4(extent, scale4(vec4(fabs(r.r0.x), fabs(r.r1.x), fabs(r.r2.x)), halfSize.x));
    extent = add4(extent, scale4(vec4(fabs(r.r0.y), fabs(r.r1.y), fabs(r.r2.y)), halfSize.y));
    extent = add4(extent, scale4(vec4(fabs(r.r0.z), fabs(r.r1.z), fabs(r.r2.z)), halfSize.z));
    box.min = sub4(centre, extent);
    box.max = add4(centre, extent);
    return box;
}

// A body whose motion this step is longer than this many bounding radii sweeps its box along the
// motion instead of growing it every way by its reach (continuous collision).
#define RUBBLE_SWEPT_REACH 8.0f

// The box of a body over its step: grown every way by its reach, or, for a body that moves more
// than RUBBLE_SWEPT_REACH bounding radii, grown by its turn alone and swept along its motion
// `v.linear dt`, so that a volley of fast bodies does not pair each with every other one it
// could have reached sideways (SatCollision::broadPhase, computeAabbs).
RUBBLE_FN BodyBox stepBoxItem(HullShape shape, RigidTransform t, BodyVelocity v, float spin,
                              float dt) {
    const float4 motion = vec4(v.linear.x * dt, v.linear.y * dt, v.linear.z * dt);
    if (!(length3(motion) > RUBBLE_SWEPT_REACH * shape.boundingRadius))
        return worldBoxItem(shape, t, RUBBLE_CONTACT_MARGIN + reachItem(v, spin, dt));
    BodyBox box = worldBoxItem(shape, t, RUBBLE_CONTACT_MARGIN + spin);
    // As glm::min and glm::max: the first operand unless the second is below (above) it.
    box.min = add4(box.min, vec4(0.0f < motion.x ? 0.0f : motion.x,
                                 0.0f < motion.y ? 0.0f : motion.y,
                                 0.0f < motion.z ? 0.0f : motion.z));
    box.max = add4(box.max, vec4(motion.x < 0.0f ? 0.0f : motion.x,
                                 motion.y < 0.0f ? 0.0f : motion.y,
                                 motion.z < 0.0f ? 0.0f : motion.z));
    return box;
}

// Closed boxes overlap (touching counts).
RUBBLE_FN int boxesOverlapItem(BodyBox a, BodyBox b) {
    return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
           a.min.z <= b.max.z && b.min.z <= a.max.z;
}

// The box's lowest point along the plane's normal is at or below its surface (reachesPlane);
// plane: unit normal (xyz), offset grown by the margin (w).
RUBBLE_FN int reachesPlaneItem(BodyBox box, float4 plane) {
    const float4 centre = scale4(add4(box.min, box.max), 0.5f);
    const float4 halfSize = scale4(sub4(box.max, box.min), 0.5f);
    return dot3(plane, centre) - dot3(abs4(plane), halfSize) <= plane.w;
}

RUBBLE_FN int finiteBoxItem(BodyBox b) {
    return isfinite(b.min.x) && isfinite(b.min.y) && isfinite(b.min.z) && isfinite(b.max.x) &&
           isfinite(b.max.y) && isfinite(b.max.z);
}

// The grid cell of a coordinate on one axis, clamped to the grid (Strips::of).
RUBBLE_FN uint gridCellItem(float x, float origin, float inverseCell, uint cells) {
    const float c = clampItem((x - origin) * inverseCell, 0.0f, (float)(cells - 1u));
    return (uint)c;
}

RUBBLE_FN uint gridKeyItem(uint x, uint y, uint z, GridParams g) {
    return (x * g.cells[1] + y) * g.cells[2] + z;
}

// Component `axis` (0, 1, 2) of v.
RUBBLE_FN float axisItem(float4 v, uint axis) {
    return axis == 0u ? v.x : (axis == 1u ? v.y : v.z);
}

// Where x lies along the sweep axis, in the sweepBits steps of the boxes' range: never
// decreasing in x, so that an entry whose start is past another's end in steps starts past it.
RUBBLE_FN uint sweepKeyItem(float x, GridParams g) {
    const uint a = g.sweepAxis;
    const float top = (float)((1u << g.sweepBits) - 1u);
    return (uint)clampItem((x - axisItem(g.origin, a)) * axisItem(g.inverseCell, a), 0.0f, top);
}

// At most this many cells along one axis of the grid.
#define RUBBLE_GRID_MAX_CELLS_PER_AXIS 1024u

// The columns over boxes whose bounds and summed widths are `sum`: the sweep axis is the one
// of widest range (the lowest of equal ones); the other two are cut into cells two mean box
// widths wide (so that a typical box touches one or two per axis), widened until there are at
// most maxCells in all; the sweep axis's range is cut into 2^sweepBits steps. Which columns a
// box is in changes how many candidates are tested, never which pairs are found.
RUBBLE_FN GridParams gridSetupItem(GridPartial sum, uint maxCells, uint sweepBits) {
    GridParams g;
    g.origin = vec4(0.0f, 0.0f, 0.0f);
    g.inverseCell = vec4(0.0f, 0.0f, 0.0f);
    g.cells[0] = g.cells[1] = g.cells[2] = g.cells[3] = 1u;
    g.largeAbove = 2u;
    g.sweepAxis = 0u;
    g.sweepBits = sweepBits;
    g.pad0 = 0u;
    if (sum.count == 0u) return g;
    g.origin = sum.lo;
    const float range[3] = {sum.hi.x - sum.lo.x, sum.hi.y - sum.lo.y, sum.hi.z - sum.lo.z};
    const float widths[3] = {sum.widthSum.x, sum.widthSum.y, sum.widthSum.z};
    uint axis = 0u;
    for (uint a = 1u; a < 3u; ++a)
        if (range[a] > range[axis]) axis = a;
    g.sweepAxis = axis;
    float cell[3];
    for (uint a = 0; a < 3u; ++a) {
        cell[a] = fmax(2.0f * widths[a] / (float)sum.count,
                       range[a] / (float)RUBBLE_GRID_MAX_CELLS_PER_AXIS);
        if (!(cell[a] > 0.0f)) cell[a] = 1.0f;
    }
    for (uint tries = 0; tries < 64u; ++tries) {
        uint total = 1u;
        for (uint a = 0; a < 3u; ++a) {
            g.cells[a] = a == axis ? 1u
                                   : (uint)fmin(floor(range[a] / cell[a]) + 1.0f,
                                                (float)RUBBLE_GRID_MAX_CELLS_PER_AXIS);
            total *= g.cells[a];
        }
        g.cells[3] = total;
        if (total <= maxCells) break;
        for (uint a = 0; a < 3u; ++a) cell[a] *= 1.26f;
    }
    if (g.cells[3] > maxCells) {
        // Never reached in practice (the widths grow by 1.26^64); one column is always right.
        g.cells[0] = g.cells[1] = g.cells[2] = g.cells[3] = 1u;
    }
    g.inverseCell = vec4(1.0f / cell[0], 1.0f / cell[1], 1.0f / cell[2]);
    // The sweep: its range in steps (none when the boxes all start at one place).
    const float steps = (float)((1u << sweepBits) - 1u);
    const float sweepScale = range[axis] > 0.0f ? steps / range[axis] : 0.0f;
    if (axis == 0u) g.inverseCell.x = sweepScale;
    if (axis == 1u) g.inverseCell.y = sweepScale;
    if (axis == 2u) g.inverseCell.z = sweepScale;
    return g;
}

RUBBLE_SHARED_END
