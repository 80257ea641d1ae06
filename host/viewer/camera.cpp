// host/viewer/camera.cpp: orbit camera, framing and projection (the same matrices the shaders use).
#include "host/viewer/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace rubble::viewer {
namespace {

constexpr float kMaxPitch = 1.55f; // just short of straight down, rad
constexpr float kOrbitRadPerPixel = 0.008f;
constexpr float kMinDistance = 0.05f;   // m
constexpr float kFramingMargin = 1.15f; // room around the framed bounds

} // namespace

Camera Camera::lookingAt(glm::vec3 eye, glm::vec3 target) {
    Camera c;
    c.target = target;
    const glm::vec3 d = eye - target;
    c.distance = std::max(glm::length(d), kMinDistance);
    const float horizontal = std::sqrt(d.x * d.x + d.z * d.z);
    c.pitch = std::clamp(std::atan2(d.y, horizontal), -kMaxPitch, kMaxPitch);
    c.yaw = horizontal > 0.0f ? std::atan2(d.x, d.z) : 0.0f;
    c.farPlane = std::max(1000.0f, 4.0f * c.distance);
    return c;
}

Camera Camera::framing(const Bounds& bounds, float aspect) {
    Camera c;
    if (bounds.empty()) return c;
    c.target = bounds.centre();
    const float radius = std::max(0.5f * glm::length(bounds.hi - bounds.lo), 0.1f);
    // The bounding sphere fits the narrower of the two fields of view.
    const float halfY = 0.5f * c.fovY;
    const float halfX = std::atan(std::tan(halfY) * aspect);
    const float half = std::min(halfX, halfY);
    c.distance = kFramingMargin * radius / std::sin(half);
    c.nearPlane = std::max(0.01f, 0.01f * c.distance);
    c.farPlane = std::max(1000.0f, 20.0f * c.distance);
    return c;
}

glm::vec3 Camera::eye() const {
    const glm::vec3 dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                        std::cos(pitch) * std::cos(yaw));
    return target + distance * dir;
}

glm::mat4 Camera::view() const {
    return glm::lookAt(eye(), target, glm::vec3(0, 1, 0));
}

glm::mat4 Camera::projection(float aspect) const {
    return glm::perspective(fovY, aspect, nearPlane, farPlane);
}

void Camera::orbit(float dxPixels, float dyPixels) {
    yaw -= dxPixels * kOrbitRadPerPixel;
    pitch = std::clamp(pitch + dyPixels * kOrbitRadPerPixel, -kMaxPitch, kMaxPitch);
}

void Camera::pan(float dxPixels, float dyPixels, int viewportHeight) {
    // One pixel moves the target by the size of a pixel at the target's depth.
    const float metresPerPixel =
        2.0f * distance * std::tan(0.5f * fovY) / float(std::max(viewportHeight, 1));
    const glm::mat4 v = view();
    const glm::vec3 right(v[0][0], v[1][0], v[2][0]);
    const glm::vec3 up(v[0][1], v[1][1], v[2][1]);
    target += metresPerPixel * (-dxPixels * right + dyPixels * up);
}

void Camera::zoom(float factor) {
    distance = std::max(distance * factor, kMinDistance);
    farPlane = std::max(farPlane, 4.0f * distance);
}

glm::vec3 projectToPixel(const Camera& camera, glm::vec3 world, int width, int height) {
    const float aspect = float(width) / float(height);
    const glm::vec4 clip = camera.projection(aspect) * camera.view() * glm::vec4(world, 1.0f);
    if (clip.w <= 0.0f) return glm::vec3(-1.0f, -1.0f, -1.0f);
    const glm::vec3 ndc = glm::vec3(clip) / clip.w;
    return {(0.5f * ndc.x + 0.5f) * float(width), (0.5f - 0.5f * ndc.y) * float(height),
            0.5f * ndc.z + 0.5f};
}

} // namespace rubble::viewer
