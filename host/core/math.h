// host/core/math.h: GLM on the host, float4 in shared records; conversions between them, once.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/shared/math.h"

namespace rubble {

using shared::float4;
using shared::Mat3;

inline glm::vec3 toVec3(float4 v) { return {v.x, v.y, v.z}; }
inline float4 toFloat4(glm::vec3 v, float w = 0.0f) { return shared::make4(v.x, v.y, v.z, w); }
// float4 quaternions are (x, y, z, w); glm::quat's constructor takes (w, x, y, z).
inline glm::quat toQuat(float4 q) { return glm::quat(q.w, q.x, q.y, q.z); }
inline float4 toFloat4(glm::quat q) { return shared::make4(q.x, q.y, q.z, q.w); }

inline glm::mat3 toMat3(const Mat3& m) {
    // glm is column-major: m[column][row].
    return glm::transpose(glm::mat3(toVec3(m.r0), toVec3(m.r1), toVec3(m.r2)));
}
inline Mat3 toShared(const glm::mat3& m) {
    const glm::mat3 t = glm::transpose(m);
    return Mat3{toFloat4(t[0]), toFloat4(t[1]), toFloat4(t[2])};
}

inline bool isFinite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool isFinite(float4 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

} // namespace rubble
