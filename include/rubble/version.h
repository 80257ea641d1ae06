// include/rubble/version.h: the version of rubble.
#pragma once

namespace rubble {
/// Semantic version of this build.
inline constexpr const char* kVersion = "0.1.0";
} // namespace rubble
