// tests/support/ci.h: whether the tests run in CI (.ci/run sets CI=1), where a test whose tool
// scripts/setup.sh installs (OpenGL, ffmpeg, matplotlib, OpenCL) fails instead of skipping.
#pragma once

#include <cstdlib>
#include <string>

namespace rubble::test {

/// True when CI is set to anything but "", "0" or "false".
inline bool inCi() {
    const char* ci = std::getenv("CI");
    return ci && *ci && std::string(ci) != "0" && std::string(ci) != "false";
}

} // namespace rubble::test
