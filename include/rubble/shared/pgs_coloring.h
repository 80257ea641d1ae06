// include/rubble/shared/pgs_coloring.h: the device's plan of the colored solve
// (kernels/coloring.cl): its bounds, the layout of its color starts, each element's priority and
// the lowest color free on its bodies. The host's plan is host/gpu/pgs_plan.cpp.
#pragma once

#include "rubble/shared/cl_compat.h"

// At most this many colors; an element that finds none free on its moving bodies, or none in
// RUBBLE_PGS_COLOR_ROUNDS rounds, goes to the overflow set, which one work-item solves in
// element order after the colors. A body's colors are one word's bits: at most 32.
#define RUBBLE_PGS_COLORS 8u
// Rounds of the device coloring: each uncolored element takes the first color free on its
// moving bodies from the one it prefers, unless an element of lower priority chose the same
// color on one of them.
#define RUBBLE_PGS_COLOR_ROUNDS 8u
// Work-items of the counting sort by color, each a run of consecutive elements, in order.
#define RUBBLE_PGS_COLOR_CHUNKS 256u
// The overflow set's index among the color ranges (after the colors).
#define RUBBLE_PGS_OVERFLOW_SET RUBBLE_PGS_COLORS
// The color starts: the first element of each color and of the overflow set, then the end
// (RUBBLE_PGS_COLORS + 2 words), then the same in rows.
#define RUBBLE_PGS_COLOR_RANGES (RUBBLE_PGS_COLORS + 2u)
#define RUBBLE_PGS_COLOR_ROW_STARTS RUBBLE_PGS_COLOR_RANGES
#define RUBBLE_PGS_COLOR_STARTS_WORDS (2u * RUBBLE_PGS_COLOR_RANGES)
// An element's color word during the coloring: not an element (a pair without points), not
// colored yet, or chosen this round (RUBBLE_PGS_COLOR_CHOSEN | color); then its color, the
// overflow set being RUBBLE_PGS_OVERFLOW_SET.
#define RUBBLE_PGS_NOT_ELEMENT 0xffffffffu
#define RUBBLE_PGS_UNCOLORED 0xfffffffeu
#define RUBBLE_PGS_COLOR_CHOSEN 0x40000000u
// A body's support level (its distance in contacts from a body that does not move) when no
// path of contacts is known, and the highest level counted.
#define RUBBLE_PGS_NO_LEVEL 0xffffu
// A body's claim on a color that no element holds.
#define RUBBLE_PGS_NO_CLAIM 0xffffffffu
// An entry of the build order for a pair without rows.
#define RUBBLE_PGS_NO_ELEMENT 0xffffffffu

RUBBLE_SHARED_BEGIN

// Element e's priority in the coloring's conflicts (lower wins): a bijection of the 32-bit words
// that keeps all ones, so that no element's priority is RUBBLE_PGS_NO_CLAIM, and scatters
// neighbouring indices, so that a chain of elements in index order (a column, pair by pair) is
// not colored one element a round.
RUBBLE_FN uint colorPriorityItem(uint e) {
    uint x = ~e * 0x9e3779b1u;
    x ^= x >> 16;
    x *= 0x85ebca6bu;
    x ^= x >> 13;
    return ~x;
}

// The first color not set in `taken` from `preferred` on, in turn through the colors, or
// RUBBLE_PGS_COLORS when every one is.
RUBBLE_FN uint freeColorItem(uint taken, uint preferred) {
    for (uint k = 0u; k < RUBBLE_PGS_COLORS; ++k) {
        const uint c = (preferred + k) % RUBBLE_PGS_COLORS;
        if (((taken >> c) & 1u) == 0u) return c;
    }
    return RUBBLE_PGS_COLORS;
}

RUBBLE_SHARED_END
