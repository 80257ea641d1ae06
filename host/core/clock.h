// host/core/clock.h: wall time for the step statistics and the build time of the kernels.
#pragma once

#include <chrono>
#include <cstdint>

namespace rubble {

using Clock = std::chrono::steady_clock;

/// A time point as nanoseconds since the clock's epoch.
inline std::int64_t steadyNs(Clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

/// Milliseconds of wall time since `start`.
inline double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

} // namespace rubble
