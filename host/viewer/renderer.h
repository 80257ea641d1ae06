// host/viewer/renderer.h: draws a DrawList with OpenGL 3.3 core into the bound framebuffer:
// instanced bodies per shape, grounds, lines, particles and the text overlay.
#pragma once

#include <memory>
#include <span>

#include <glm/glm.hpp>

#include "rubble/shape.h"
#include "host/viewer/camera.h"
#include "host/viewer/draw_list.h"
#include "rubble/error.h"

namespace rubble::viewer {

/// Colours the renderer uses outside the bodies: linear RGB.
struct Palette {
    glm::vec3 background{0.030f, 0.045f, 0.070f};
    glm::vec3 ground{0.36f, 0.36f, 0.35f};
    glm::vec3 particles{0.30f, 0.75f, 1.0f};
};

/// Draws frames. Needs a current OpenGL 3.3 core context for its whole life (create, draw,
/// destroy on the same context). Move-only.
class Renderer {
  public:
    /// Compiles the programs and uploads one mesh per shape (index = shape index).
    /// Errors: Device naming the GL call, with the compiler's log.
    static Result<Renderer> create(std::span<const ShapeGeometry> shapes);

    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;
    ~Renderer();

    Palette& palette();
    /// The text overlay's scale: 1 draws the bitmap font's pixels as they are.
    void setTextScale(float scale);

    /// Clears the bound framebuffer and draws the frame into a viewport of width x height.
    void draw(const DrawList& frame, const Camera& camera, int width, int height);

  private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// The direction towards the light, world frame, unit (from above, front and side).
glm::vec3 lightDirection();

} // namespace rubble::viewer
