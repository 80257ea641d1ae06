// include/rubble/shared/cl_compat.h: the one place that tells the host compiler from the OpenCL C
// compiler. Everything under rubble/shared compiles in both; this file supplies float4, uint,
// RUBBLE_FN and the namespace brackets on the host.
#pragma once

#ifdef __OPENCL_C_VERSION__

// Same arithmetic on both sides: no fused multiply-add unless written.
#pragma OPENCL FP_CONTRACT OFF
#define RUBBLE_FN static inline
#define RUBBLE_SHARED_BEGIN
#define RUBBLE_SHARED_END
#define RUBBLE_STATIC_ASSERT_SIZE(type, bytes)
// A pointer into device memory (the flattened hulls read by the narrow phase); plain on the host.
#define RUBBLE_GLOBAL __global
// The joints' position projection factors its matrices in double, as the CPU's does, on a device
// with fp64, else in float: the tuning parameter jointDouble (host/gpu/tuning.h), passed with -D.
#if defined(RUBBLE_JOINT_DOUBLE) && RUBBLE_JOINT_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double JointReal;
#else
typedef float JointReal;
#endif

#else

#include <cmath>
#include <cstdint>

namespace rubble {
namespace shared {
// The host's picture of OpenCL's float4: 16 bytes, 16-byte aligned.
struct alignas(16) float4 {
    float x, y, z, w;
};
typedef std::uint32_t uint;
typedef std::uint64_t ulong;
typedef double JointReal; // the joints' projection in double, as host/dynamics/joint_positions.cpp
using std::fabs;
using std::floor;
using std::isfinite;
using std::fmax;
using std::fmin;
using std::sqrt;
} // namespace shared
} // namespace rubble

#define RUBBLE_FN inline
#define RUBBLE_SHARED_BEGIN                                                                        \
    namespace rubble {                                                                             \
    namespace shared {
#define RUBBLE_SHARED_END                                                                          \
    }                                                                                              \
    }
#define RUBBLE_STATIC_ASSERT_SIZE(type, bytes)                                                     \
    static_assert(sizeof(type) == (bytes), #type " must match its OpenCL layout")
#define RUBBLE_GLOBAL

#endif
