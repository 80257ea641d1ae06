// host/core/assert.h: RUBBLE_ASSERT guards invariants of rubble's own code, never input.
#pragma once

#include <cstdio>
#include <cstdlib>

#define RUBBLE_ASSERT(cond)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            std::fprintf(stderr, "rubble: internal error: %s failed at %s:%d\n", #cond, __FILE__,  \
                         __LINE__);                                                                \
            std::abort();                                                                          \
        }                                                                                          \
    } while (0)
