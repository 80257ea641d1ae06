// host/viewer/offscreen_context.h: an OpenGL 3.3 core context with no window, for rendering to
// images: EGL (Mesa's surfaceless platform, else a pbuffer) or, failing that, a hidden GLFW
// window on the current X display or on an Xvfb server started for it.
#pragma once

#include <memory>
#include <string>

#include "host/viewer/viewer.h"
#include "rubble/error.h"

namespace rubble::viewer {

/// A current off-screen context; current on the creating thread until destroyed. Move-only.
class OffscreenContext {
  public:
    /// Makes a context and makes it current. Errors: Device saying what each way tried
    /// returned (EGL errors by name, GLFW's messages).
    static Result<OffscreenContext> create(ContextKind kind = ContextKind::Auto);

    OffscreenContext(OffscreenContext&&) noexcept;
    OffscreenContext& operator=(OffscreenContext&&) noexcept;
    ~OffscreenContext();

    /// How the context was made and the renderer, e.g. `EGL surfaceless: llvmpipe (...)`.
    const std::string& description() const;

  private:
    struct Impl;
    explicit OffscreenContext(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

} // namespace rubble::viewer
