// host/viewer/camera.h: the viewer's camera: an orbit around a target, the matrices the renderer
// draws with, automatic framing of a scene's bounds, and world-to-pixel projection.
#pragma once

#include <glm/glm.hpp>

namespace rubble::viewer {

/// An axis-aligned box, world frame, m; empty until a point is added.
struct Bounds {
    glm::vec3 lo{1e30f};
    glm::vec3 hi{-1e30f};

    bool empty() const { return lo.x > hi.x; }
    void add(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void addSphere(glm::vec3 centre, float radius) {
        add(centre - glm::vec3(radius));
        add(centre + glm::vec3(radius));
    }
    glm::vec3 centre() const { return 0.5f * (lo + hi); }
};

/// A perspective camera orbiting `target`: yaw about the world y axis, pitch above the
/// horizontal, both in radians; distance in m. y is up (SCENE_FORMAT.md).
struct Camera {
    glm::vec3 target{0.0f};
    float distance = 10.0f;
    float yaw = 0.6f;
    float pitch = 0.45f;
    float fovY = 0.785398f; ///< vertical field of view, rad (45 degrees)
    float nearPlane = 0.05f;
    float farPlane = 1000.0f;

    /// The camera looking from `eye` at `target`.
    static Camera lookingAt(glm::vec3 eye, glm::vec3 target);

    /// The camera placed so that `bounds` fills the view at the given aspect (width / height),
    /// seen from the default yaw and pitch.
    static Camera framing(const Bounds& bounds, float aspect);

    glm::vec3 eye() const;
    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const;

    /// Mouse controls: turn by pixel deltas, pan the target in the view plane, zoom by a factor.
    void orbit(float dxPixels, float dyPixels);
    void pan(float dxPixels, float dyPixels, int viewportHeight);
    void zoom(float factor);
};

/// Where a world point lands in an image of width x height pixels: x to the right, y down from
/// the top row, in pixels; z is the depth in [0, 1]. Points behind the camera give z outside.
glm::vec3 projectToPixel(const Camera& camera, glm::vec3 world, int width, int height);

} // namespace rubble::viewer
