// kernels/broad_phase.cl: entry points of the SAT broad phase on the device (computeAabbs, then
// findPairs by sweep and prune in columns): world boxes, the columns and their entries sorted
// along the sweep axis, candidate pairs, and the pairs sorted by (a, b). The math is in
// rubble/shared/broad_phase.h; the CPU twin is SatCollision::broadPhase with findPairs
// (host/collision/sat_collision.cpp, broad_phase.cpp).
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/group.h"
#include "rubble/shared/narrow_phase.h"

// The pair (i, j) in the order a < b, into *pair, and whether it may collide: joined bodies do
// not (`joined`: the joints' pairs, sorted).
static int collidingPair(const uint i, const uint j, const uint joinedCount,
                         __global const BodyPairRecord* joined, BodyPairRecord* pair) {
    pair->a = min(i, j);
    pair->b = max(i, j);
    return findPairItem(*pair, joinedCount, joined) == joinedCount;
}

// Appends the pair (i, j) unless the bodies are joined; past the capacity it only counts, and
// the host grows the buffer.
static void appendPair(const uint i, const uint j, const uint joinedCount,
                       __global const BodyPairRecord* joined, const uint capacity,
                       __global BodyPairRecord* pairs, __global uint* status) {
    BodyPairRecord p;
    if (!collidingPair(i, j, joinedCount, joined, &p)) return;
    const uint at = atomic_inc(&status[RUBBLE_STATUS_PAIRS]);
    if (at < capacity) pairs[at] = p;
}

// One work-item per body: its world box grown by the margin and its reach this step, or swept
// along its motion if it is fast (stepBoxItem) (min.w: 1
// when inactive), its spin (the narrow phase's pair margin), its broad-phase flags. A plane's
// box holds its world plane instead (min: unit normal, offset grown by the margin).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BROAD, 1, 1))) void
computeAabbs(const uint count, const float dt, __global const HullShape* shapes,
             __global const uint* shapeOf, __global const BodyPose* poses,
             __global const BodyVelocity* velocities, __global const uint* flags,
             __global BodyBox* boxes, __global float* spin, __global uint* broadFlags) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const HullShape shape = shapes[shapeOf[i]];
    const uint f = flags[i];
    const BodyVelocity v = velocities[i];
    const float turning = spinItem(v, shape.boundingRadius, dt);
    const RigidTransform t = transformOfPose(poses[i]);
    // A kinematic body that does not move pairs as a static one; one that moves pairs with
    // sleeping bodies too, so that it wakes them.
    const int still = (f & RUBBLE_BODY_KINEMATIC) && !(f & RUBBLE_BODY_WAKING);
    uint bf = (still || (f & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP))) ? RUBBLE_BROAD_INACTIVE
                                                                          : 0u;
    BodyBox box;
    if (shape.kind == RUBBLE_SHAPE_PLANE) {
        const float4 plane = worldPlaneItem(shape, t);
        box.min = make4(plane.x, plane.y, plane.z, plane.w + RUBBLE_CONTACT_MARGIN);
        box.max = make4(0.0f, 0.0f, 0.0f, 0.0f);
        bf |= RUBBLE_BROAD_NO_BOX;
    } else {
        box = stepBoxItem(shape, t, v, turning, dt);
        if (!finiteBoxItem(box) || (f & RUBBLE_BODY_ABSENT)) bf |= RUBBLE_BROAD_NO_BOX;
        box.min.w = (bf & RUBBLE_BROAD_INACTIVE) ? 1.0f : 0.0f;
    }
    boxes[i] = box;
    spin[i] = turning;
    broadFlags[i] = bf;
}

// The boxes' bounds and mean widths, RUBBLE_SORT_ITEMS work-items each over a chunk of the
// bodies (then gridSetup adds the chunks up in order).
__kernel void gridBounds(const uint count, __global const BodyBox* boxes,
                         __global const uint* broadFlags, __global GridPartial* partials) {
    const uint t = get_global_id(0);
    if (t >= RUBBLE_SORT_ITEMS) return;
    const uint chunk = (count + RUBBLE_SORT_ITEMS - 1u) / RUBBLE_SORT_ITEMS;
    const uint begin = min(count, t * chunk), end = min(count, begin + chunk);
    GridPartial p;
    p.lo = vec4(INFINITY, INFINITY, INFINITY);
    p.hi = vec4(-INFINITY, -INFINITY, -INFINITY);
    p.widthSum = vec4(0.0f, 0.0f, 0.0f);
    p.count = 0u;
    p.pad0 = p.pad1 = p.pad2 = 0u;
    for (uint i = begin; i < end; ++i) {
        if (broadFlags[i] & RUBBLE_BROAD_NO_BOX) continue;
        const BodyBox b = boxes[i];
        p.lo = vec4(fmin(p.lo.x, b.min.x), fmin(p.lo.y, b.min.y), fmin(p.lo.z, b.min.z));
        p.hi = vec4(fmax(p.hi.x, b.max.x), fmax(p.hi.y, b.max.y), fmax(p.hi.z, b.max.z));
        p.widthSum = add4(p.widthSum, sub4(b.max, b.min));
        ++p.count;
    }
    partials[t] = p;
}

// One work-item: the columns over the boxes (gridSetupItem).
__kernel void gridSetup(const uint maxCells, const uint sweepBits,
                        __global const GridPartial* partials, __global GridParams* grid) {
    if (get_global_id(0) != 0) return;
    GridPartial sum;
    sum.lo = vec4(INFINITY, INFINITY, INFINITY);
    sum.hi = vec4(-INFINITY, -INFINITY, -INFINITY);
    sum.widthSum = vec4(0.0f, 0.0f, 0.0f);
    sum.count = 0u;
    for (uint t = 0; t < RUBBLE_SORT_ITEMS; ++t) {
        const GridPartial p = partials[t];
        sum.lo = vec4(fmin(sum.lo.x, p.lo.x), fmin(sum.lo.y, p.lo.y), fmin(sum.lo.z, p.lo.z));
        sum.hi = vec4(fmax(sum.hi.x, p.hi.x), fmax(sum.hi.y, p.hi.y), fmax(sum.hi.z, p.hi.z));
        sum.widthSum = add4(sum.widthSum, p.widthSum);
        sum.count += p.count;
    }
    grid[0] = gridSetupItem(sum, maxCells, sweepBits);
}

// One work-item per body with a box: its (key, body) entries, one per column its box touches (at
// most two per axis), keyed by the column and, below it, where the box starts along the sweep
// axis; a larger box goes to the list of large bodies instead. The group's entries take their
// slots together (the sort by key that follows orders them).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BROAD, 1, 1))) void
gridEntries(const uint count, __global const BodyBox* boxes, __global uint* broadFlags,
            __global const GridParams* grid, __global uint* status, __global uint* keys,
            __global uint* values, __global uint* large) {
    __local uint slots[2];
    const uint i = get_global_id(0);
    const uint bf = i < count ? broadFlags[i] : RUBBLE_BROAD_NO_BOX;
    const GridParams g = grid[0];
    uint x0 = 0u, x1 = 0u, y0 = 0u, y1 = 0u, z0 = 0u, z1 = 0u, n = 0u, start = 0u;
    if (!(bf & RUBBLE_BROAD_NO_BOX)) {
        const BodyBox b = boxes[i];
        start = sweepKeyItem(axisItem(b.min, g.sweepAxis), g);
        x0 = gridCellItem(b.min.x, g.origin.x, g.inverseCell.x, g.cells[0]);
        x1 = gridCellItem(b.max.x, g.origin.x, g.inverseCell.x, g.cells[0]);
        y0 = gridCellItem(b.min.y, g.origin.y, g.inverseCell.y, g.cells[1]);
        y1 = gridCellItem(b.max.y, g.origin.y, g.inverseCell.y, g.cells[1]);
        z0 = gridCellItem(b.min.z, g.origin.z, g.inverseCell.z, g.cells[2]);
        z1 = gridCellItem(b.max.z, g.origin.z, g.inverseCell.z, g.cells[2]);
        if (x1 - x0 >= g.largeAbove || y1 - y0 >= g.largeAbove || z1 - z0 >= g.largeAbove) {
            broadFlags[i] = bf | RUBBLE_BROAD_LARGE;
            large[atomic_inc(&status[RUBBLE_STATUS_LARGE])] = i;
        } else {
            n = (x1 - x0 + 1u) * (y1 - y0 + 1u) * (z1 - z0 + 1u);
        }
    }
    uint at = groupReserve(slots, n, &status[RUBBLE_STATUS_GRID_ENTRIES]);
    if (n == 0u) return;
    for (uint x = x0; x <= x1; ++x)
        for (uint y = y0; y <= y1; ++y)
            for (uint z = z0; z <= z1; ++z) {
                keys[at] = (gridKeyItem(x, y, z, g) << g.sweepBits) | start;
                values[at] = i;
                ++at;
            }
}

// The entries sorted by key: each entry's box in the same order, so that a column's boxes are
// read from consecutive memory.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BROAD, 1, 1))) void
gatherCellBoxes(__global const uint* status, __global const uint* values,
                __global const BodyBox* boxes, __global BodyBox* cellBoxes) {
    const uint n = status[RUBBLE_STATUS_GRID_ENTRIES];
    const uint e = get_global_id(0);
    if (e >= n) return;
    cellBoxes[e] = boxes[values[e]];
}

// Pairs a work-item of findCellPairs holds before the group takes their slots together; more
// in one round take a slot each.
#define RUBBLE_CELL_PAIRS_HELD 8u

// Each entry is tested against the later entries of its column up to the first that starts past
// its end along the sweep axis (in sweep steps: a key above `limit`, which also ends the column).
// A pair that shares several columns is reported by the column holding the lower corner of the
// overlap of its boxes only; two inactive bodies are never paired. Rounds of one entry per
// work-item: each round the group's pairs take their slots with one atomic (groupReserve);
// countPairs and placePairs then order them by (a, b) whatever their slots.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BROAD, 1, 1))) void
findCellPairs(__global const uint* keys, __global const uint* values,
              __global const BodyBox* cellBoxes, __global const GridParams* grid,
              const uint joinedCount, __global const BodyPairRecord* joined, const uint capacity,
              __global BodyPairRecord* pairs, __global uint* status) {
    __local uint slots[2];
    const uint n = status[RUBBLE_STATUS_GRID_ENTRIES];
    const GridParams g = grid[0];
    for (uint round = get_group_id(0) * get_local_size(0); round < n;
         round += get_global_size(0)) {
        const uint e = round + get_local_id(0);
        BodyPairRecord held[RUBBLE_CELL_PAIRS_HELD];
        uint count = 0u;
        const uint key = e < n ? keys[e] : 0u, cell = key >> g.sweepBits;
        const BodyBox bi = cellBoxes[e < n ? e : 0u];
        const uint limit = (cell << g.sweepBits) | sweepKeyItem(axisItem(bi.max, g.sweepAxis), g);
        for (uint f = e + 1u; f < n && keys[f] <= limit; ++f) {
            const BodyBox bj = cellBoxes[f];
            if (bi.min.w + bj.min.w == 2.0f || !boxesOverlapItem(bi, bj)) continue;
            const uint corner = gridKeyItem(
                gridCellItem(fmax(bi.min.x, bj.min.x), g.origin.x, g.inverseCell.x, g.cells[0]),
                gridCellItem(fmax(bi.min.y, bj.min.y), g.origin.y, g.inverseCell.y, g.cells[1]),
                gridCellItem(fmax(bi.min.z, bj.min.z), g.origin.z, g.inverseCell.z, g.cells[2]),
                g);
            if (corner != cell) continue;
            if (count == RUBBLE_CELL_PAIRS_HELD) {
                appendPair(values[e], values[f], joinedCount, joined, capacity, pairs, status);
                continue;
            }
            BodyPairRecord p;
            if (collidingPair(values[e], values[f], joinedCount, joined, &p)) held[count++] = p;
        }
        const uint at = groupReserve(slots, count, &status[RUBBLE_STATUS_PAIRS]);
        for (uint k = 0; k < count; ++k)
            if (at + k < capacity) pairs[at + k] = held[k];
    }
}

// One work-item per body: its pairs with the planes (an active body whose box reaches below
// one) and with the large bodies (each pair of two large bodies once, from the lower index).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BROAD, 1, 1))) void
findLargePairs(const uint count, __global const BodyBox* boxes, __global const uint* broadFlags,
               const uint planeCount, __global const uint* planes, __global const uint* large,
               const uint joinedCount, __global const BodyPairRecord* joined,
               const uint capacity, __global BodyPairRecord* pairs, __global uint* status) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const uint bf = broadFlags[i];
    if (bf & RUBBLE_BROAD_NO_BOX) return;
    const BodyBox box = boxes[i];
    if (!(bf & RUBBLE_BROAD_INACTIVE))
        for (uint k = 0; k < planeCount; ++k) {
            const uint p = planes[k];
            if (p != i && reachesPlaneItem(box, boxes[p].min))
                appendPair(p, i, joinedCount, joined, capacity, pairs, status);
        }
    const uint largeCount = status[RUBBLE_STATUS_LARGE];
    for (uint k = 0; k < largeCount; ++k) {
        const uint j = large[k];
        if (j == i || ((bf & RUBBLE_BROAD_LARGE) && j < i)) continue;
        if ((bf & RUBBLE_BROAD_INACTIVE) && (broadFlags[j] & RUBBLE_BROAD_INACTIVE)) continue;
        if (boxesOverlapItem(box, boxes[j]))
            appendPair(i, j, joinedCount, joined, capacity, pairs, status);
    }
}

// The pairs in the order of (a, b): count per body a, place (after an exclusive scan of the
// counts) and sort each body's few partners by b, as the CPU's sortPairsByBody.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
countPairs(const uint capacity, __global const uint* status,
           __global const BodyPairRecord* pairs, __global uint* bodyCount) {
    const uint n = min(status[RUBBLE_STATUS_PAIRS], capacity);
    const ItemRange r = itemRange(n);
    for (uint p = r.first; p < r.end; p += r.step)
        atomic_inc(&bodyCount[pairs[p].a]);
}

__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
placePairs(const uint capacity, __global const uint* status, __global const BodyPairRecord* in,
           __global uint* cursor, __global BodyPairRecord* out) {
    const uint n = min(status[RUBBLE_STATUS_PAIRS], capacity);
    const ItemRange r = itemRange(n);
    for (uint p = r.first; p < r.end; p += r.step) {
        const BodyPairRecord pair = in[p];
        out[atomic_inc(&cursor[pair.a])] = pair;
    }
}

__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BROAD, 1, 1))) void
sortPairLists(const uint count, __global const uint* bodyStart, __global BodyPairRecord* pairs) {
    const uint a = get_global_id(0);
    if (a >= count) return;
    const uint begin = bodyStart[a], end = bodyStart[a + 1u];
    for (uint i = begin + 1u; i < end; ++i) {
        const BodyPairRecord p = pairs[i];
        uint j = i;
        for (; j > begin && pairs[j - 1u].b > p.b; --j) pairs[j] = pairs[j - 1u];
        pairs[j] = p;
    }
}
