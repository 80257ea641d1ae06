// kernels/coloring.cl: entry points of the device's plan of the colored solve: the step's
// elements (the joints, then the pairs whose summary has points) colored in rounds with at most
// RUBBLE_PGS_COLORS colors and an overflow set, then sorted by color with their rows' places.
// The host's plan, its twin in purpose, is host/gpu/pgs_plan.cpp; the bounds and the priority are
// in rubble/shared/pgs_coloring.h.
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/pgs_coloring.h"
#include "rubble/shared/pgs_element.h"

// Element e of the step: joint e (e < jointCount), else pair e - jointCount; its bodies and which
// of them move (RUBBLE_PGS_MOVES_*): a pair's from its summary, a joint's from the bodies' inverse
// masses, as the sweeps decide (jointMoves).
typedef struct PlanElement {
    uint a, b, moves;
} PlanElement;
static PlanElement planElement(const uint e, const uint jointCount,
                               __global const BodyPairRecord* pairs, __global const uint* pairRows,
                               __global const PgsJoint* joints, __global const JacobiBody* bodies) {
    PlanElement x;
    if (e < jointCount) {
        x.a = joints[e].a;
        x.b = joints[e].b;
        x.moves = jointMoves(bodies[x.a], bodies[x.b]);
    } else {
        x.a = pairs[e - jointCount].a;
        x.b = pairs[e - jointCount].b;
        x.moves = pairRows[e - jointCount] & (RUBBLE_PGS_MOVES_A | RUBBLE_PGS_MOVES_B);
    }
    return x;
}

// The step's elements: the joints and this round's pairs.
static uint planElements(const uint jointCount, const uint capacity,
                         __global const uint* pairCount) {
    return jointCount + min(pairCount[0], capacity);
}

// Grid-stride, before the rounds: every joint and every pair with points uncolored, the rest no
// element; every body's colors none, and its level 0 if it does not move, else unknown until
// relaxLevels.
__kernel void beginColoring(const uint jointCount, const uint capacity,
                            __global const uint* pairCount, __global const uint* pairRows,
                            __global uint* colorOf, const uint bodyCount,
                            __global const JacobiBody* bodies, __global uint* bodyColors,
                            __global uint* level) {
    const uint n = planElements(jointCount, capacity, pairCount);
    for (uint e = get_global_id(0); e < n; e += get_global_size(0))
        colorOf[e] = e < jointCount || (pairRows[e - jointCount] & RUBBLE_PGS_POINTS)
                         ? RUBBLE_PGS_UNCOLORED
                         : RUBBLE_PGS_NOT_ELEMENT;
    for (uint i = get_global_id(0); i < bodyCount; i += get_global_size(0)) {
        bodyColors[i] = 0u;
        level[i] = jointInverseMassItem(bodies[i]) > 0.0f ? RUBBLE_PGS_NO_LEVEL : 0u;
    }
}

// Grid-stride over the pairs with rows, one step of a breadth-first search kept from step to
// step: each moving body's level is one more than the lowest of last step's levels of the bodies
// it touches (a body that does not move is 0), so that the levels follow a pile as it settles, a
// contact a step, for one launch a step. Reads last step's levels only: the result does not
// depend on the work-items' order.
__kernel void relaxLevels(const uint jointCount, const uint capacity,
                          __global const uint* pairCount, __global const BodyPairRecord* pairs,
                          __global const uint* pairRows, __global const uint* lastLevel,
                          __global uint* level) {
    const uint n = min(pairCount[0], capacity);
    for (uint p = get_global_id(0); p < n; p += get_global_size(0)) {
        const uint summary = pairRows[p];
        if (!(summary & RUBBLE_PGS_POINTS)) continue;
        const uint a = pairs[p].a, b = pairs[p].b;
        const uint la = summary & RUBBLE_PGS_MOVES_A ? lastLevel[a] : 0u;
        const uint lb = summary & RUBBLE_PGS_MOVES_B ? lastLevel[b] : 0u;
        if (summary & RUBBLE_PGS_MOVES_A) atomic_min(&level[a], min(lb + 1u, RUBBLE_PGS_NO_LEVEL));
        if (summary & RUBBLE_PGS_MOVES_B) atomic_min(&level[b], min(la + 1u, RUBBLE_PGS_NO_LEVEL));
    }
}

// The color an element prefers: its lower body's level, through the colors in turn, so that a
// column of bodies runs up through the colors and one sweep of the colors in order carries its
// support up as many bodies as there are colors (the host's coloring by support does the same
// from the color of the element below). A joint, or an element no support reaches, prefers 0.
static uint preferredColor(const uint e, const uint jointCount, const PlanElement x,
                           __global const uint* level) {
    if (e < jointCount) return 0u;
    const uint la = x.moves & RUBBLE_PGS_MOVES_A ? level[x.a] : 0u;
    const uint lb = x.moves & RUBBLE_PGS_MOVES_B ? level[x.b] : 0u;
    const uint lower = min(la, lb);
    return lower == RUBBLE_PGS_NO_LEVEL ? 0u : lower % RUBBLE_PGS_COLORS;
}

// A round's first half, grid-stride: each uncolored element chooses the first color free on its
// moving bodies from the one it prefers (none free: the overflow set) and claims it on each of
// them with its priority; the lowest priority holds each (body, color).
__kernel void chooseColors(const uint jointCount, const uint capacity,
                           __global const uint* pairCount, __global const BodyPairRecord* pairs,
                           __global const uint* pairRows, __global const PgsJoint* joints,
                           __global const JacobiBody* bodies, __global uint* colorOf,
                           __global const uint* level, __global const uint* bodyColors,
                           __global uint* claims) {
    const uint n = planElements(jointCount, capacity, pairCount);
    for (uint e = get_global_id(0); e < n; e += get_global_size(0)) {
        if (colorOf[e] != RUBBLE_PGS_UNCOLORED) continue;
        const PlanElement x = planElement(e, jointCount, pairs, pairRows, joints, bodies);
        const uint taken = (x.moves & RUBBLE_PGS_MOVES_A ? bodyColors[x.a] : 0u) |
                           (x.moves & RUBBLE_PGS_MOVES_B ? bodyColors[x.b] : 0u);
        const uint c = freeColorItem(taken, preferredColor(e, jointCount, x, level));
        if (c == RUBBLE_PGS_COLORS) {
            colorOf[e] = RUBBLE_PGS_OVERFLOW_SET;
            continue;
        }
        colorOf[e] = RUBBLE_PGS_COLOR_CHOSEN | c;
        const uint p = colorPriorityItem(e);
        if (x.moves & RUBBLE_PGS_MOVES_A) atomic_min(&claims[x.a * RUBBLE_PGS_COLORS + c], p);
        if (x.moves & RUBBLE_PGS_MOVES_B) atomic_min(&claims[x.b * RUBBLE_PGS_COLORS + c], p);
    }
}

// A round's second half, grid-stride: an element that holds its color on each moving body takes
// it (no other element of that color shares a moving body with it); the others try again next
// round. Each element clears the claims it holds, so that every claim is clear for the next
// round: another element reads either the holder's priority or no claim, and loses either way.
// The winners are those of the lowest priority per (body, color), whatever the order the
// work-items run in: the coloring depends on the input alone.
__kernel void takeColors(const uint jointCount, const uint capacity, __global const uint* pairCount,
                         __global const BodyPairRecord* pairs, __global const uint* pairRows,
                         __global const PgsJoint* joints, __global const JacobiBody* bodies,
                         __global uint* colorOf, __global const uint* level,
                         __global uint* bodyColors, __global uint* claims) {
    const uint n = planElements(jointCount, capacity, pairCount);
    for (uint e = get_global_id(0); e < n; e += get_global_size(0)) {
        const uint chosen = colorOf[e];
        if (chosen >= RUBBLE_PGS_UNCOLORED || !(chosen & RUBBLE_PGS_COLOR_CHOSEN)) continue;
        const PlanElement x = planElement(e, jointCount, pairs, pairRows, joints, bodies);
        const uint c = chosen & ~RUBBLE_PGS_COLOR_CHOSEN, p = colorPriorityItem(e);
        const uint slotA = x.a * RUBBLE_PGS_COLORS + c, slotB = x.b * RUBBLE_PGS_COLORS + c;
        const int movesA = (x.moves & RUBBLE_PGS_MOVES_A) != 0u;
        const int movesB = (x.moves & RUBBLE_PGS_MOVES_B) != 0u;
        // Read and cleared in one: only the holder's priority matches, so only its swap clears.
        const int holdsA = !movesA || atomic_cmpxchg(&claims[slotA], p, RUBBLE_PGS_NO_CLAIM) == p;
        const int holdsB = !movesB || atomic_cmpxchg(&claims[slotB], p, RUBBLE_PGS_NO_CLAIM) == p;
        const int holds = holdsA && holdsB;
        if (!holds) {
            colorOf[e] = RUBBLE_PGS_UNCOLORED;
            continue;
        }
        if (movesA) atomic_or(&bodyColors[x.a], 1u << c);
        if (movesB) atomic_or(&bodyColors[x.b], 1u << c);
        colorOf[e] = c;
    }
}

// Element e's set after the rounds: its color, or the overflow set (none free, or still
// uncolored after the last round); RUBBLE_PGS_NOT_ELEMENT for a pair without rows.
static uint colorSet(const uint colored) {
    if (colored == RUBBLE_PGS_NOT_ELEMENT) return colored;
    return colored < RUBBLE_PGS_COLORS ? colored : RUBBLE_PGS_OVERFLOW_SET;
}

// Element e's points (a joint has none).
static uint planPoints(const uint e, const uint jointCount, __global const uint* pairRows) {
    return e < jointCount ? 0u : pairRows[e - jointCount] & RUBBLE_PGS_POINTS;
}

// The run of elements of chunk t (of RUBBLE_PGS_COLOR_CHUNKS) of the counting sort.
static uint2 chunkRun(const uint t, const uint n) {
    const uint per = (n + RUBBLE_PGS_COLOR_CHUNKS - 1u) / RUBBLE_PGS_COLOR_CHUNKS;
    return (uint2)(min(t * per, n), min(t * per + per, n));
}

// The counting sort, one work-item per chunk: its elements and rows in each set. chunkCounts
// holds the elements by (set, chunk), then the rows the same way.
__kernel void countColors(const uint jointCount, const uint capacity,
                          __global const uint* pairCount, __global const uint* pairRows,
                          __global const uint* colorOf, __global uint* chunkCounts) {
    const uint t = get_global_id(0);
    if (t >= RUBBLE_PGS_COLOR_CHUNKS) return;
    uint count[RUBBLE_PGS_COLORS + 1u], rows[RUBBLE_PGS_COLORS + 1u];
    for (uint c = 0u; c <= RUBBLE_PGS_COLORS; ++c) count[c] = rows[c] = 0u;
    const uint2 run = chunkRun(t, planElements(jointCount, capacity, pairCount));
    for (uint e = run.x; e < run.y; ++e) {
        const uint c = colorSet(colorOf[e]);
        if (c == RUBBLE_PGS_NOT_ELEMENT) continue;
        ++count[c];
        rows[c] += planPoints(e, jointCount, pairRows);
    }
    const uint sets = RUBBLE_PGS_COLORS + 1u, chunks = RUBBLE_PGS_COLOR_CHUNKS;
    for (uint c = 0u; c < sets; ++c) {
        chunkCounts[c * chunks + t] = count[c];
        chunkCounts[(sets + c) * chunks + t] = rows[c];
    }
}

// One work-item: the exclusive prefix sums over (set, chunk) of the chunks' elements and rows,
// in place, and each set's first element and row with the ends (the color starts).
__kernel void scanColors(__global uint* chunkCounts, __global uint* colorStarts) {
    if (get_global_id(0) != 0u) return;
    const uint sets = RUBBLE_PGS_COLORS + 1u, chunks = RUBBLE_PGS_COLOR_CHUNKS;
    uint elements = 0u, rows = 0u;
    for (uint c = 0u; c < sets; ++c) {
        colorStarts[c] = elements;
        colorStarts[RUBBLE_PGS_COLOR_ROW_STARTS + c] = rows;
        for (uint t = 0u; t < chunks; ++t) {
            const uint k = chunkCounts[c * chunks + t], r = chunkCounts[(sets + c) * chunks + t];
            chunkCounts[c * chunks + t] = elements;
            chunkCounts[(sets + c) * chunks + t] = rows;
            elements += k;
            rows += r;
        }
    }
    colorStarts[sets] = elements;
    colorStarts[RUBBLE_PGS_COLOR_ROW_STARTS + sets] = rows;
}

// The counting sort's scatter, one work-item per chunk, stable: each element's record at its
// set's next place (a set's elements in element order: the joints, then the pairs in pair
// order), its points' rows in a run from its set's next row, and each pair's place in the build
// order (RUBBLE_PGS_NO_ELEMENT for a pair without rows).
__kernel void placeColors(const uint jointCount, const uint capacity,
                          __global const uint* pairCount, __global const BodyPairRecord* pairs,
                          __global const uint* pairRows, __global const PgsJoint* joints,
                          __global const uint* colorOf, __global const uint* chunkCounts,
                          __global PgsElement* elements, __global uint* buildOrder) {
    const uint t = get_global_id(0);
    if (t >= RUBBLE_PGS_COLOR_CHUNKS) return;
    const uint sets = RUBBLE_PGS_COLORS + 1u, chunks = RUBBLE_PGS_COLOR_CHUNKS;
    uint next[RUBBLE_PGS_COLORS + 1u], nextRow[RUBBLE_PGS_COLORS + 1u];
    for (uint c = 0u; c < sets; ++c) {
        next[c] = chunkCounts[c * chunks + t];
        nextRow[c] = chunkCounts[(sets + c) * chunks + t];
    }
    const uint2 run = chunkRun(t, planElements(jointCount, capacity, pairCount));
    for (uint e = run.x; e < run.y; ++e) {
        const uint c = colorSet(colorOf[e]);
        if (c == RUBBLE_PGS_NOT_ELEMENT) {
            buildOrder[e - jointCount] = RUBBLE_PGS_NO_ELEMENT;
            continue;
        }
        PgsElement x;
        const uint points = planPoints(e, jointCount, pairRows);
        if (e < jointCount) {
            x.a = joints[e].a;
            x.b = joints[e].b;
            x.id = RUBBLE_PGS_JOINT_ELEMENT | e;
            x.rows = 0u;
        } else {
            x.a = pairs[e - jointCount].a;
            x.b = pairs[e - jointCount].b;
            x.id = e - jointCount;
            x.rows = pairRows[e - jointCount];
            buildOrder[e - jointCount] = next[c];
        }
        for (uint k = 0u; k < 4u; ++k) x.normal[k] = k < points ? nextRow[c] + k : 0u;
        nextRow[c] += points;
        elements[next[c]++] = x;
    }
}
