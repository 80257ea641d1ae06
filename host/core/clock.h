// host/core/clock.h: wall time for the step statistics and the build time of the kernels.
#pragma once

#include <chrono>

namespace rubble {

using Clock = std::chrono::steady_clock;

/// Milliseconds of wall time since `start`.
inline double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

} // namespace rubble
