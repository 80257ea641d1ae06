// kernels/layout.cl: measures every shared struct on the device for tests/gpu/layout_test.cpp.
#include "rubble/shared/layout.h"

#define RUBBLE_MEASURE_SIZE(T) out[n++] = (uint)sizeof(T);
#define RUBBLE_MEASURE_OFFSET(T, f) out[n++] = (uint)__builtin_offsetof(T, f);

__kernel void measureLayout(__global uint* out) {
    if (get_global_id(0) != 0) return;
    uint n = 0;
    RUBBLE_SHARED_LAYOUT(RUBBLE_MEASURE_SIZE, RUBBLE_MEASURE_OFFSET)
}
