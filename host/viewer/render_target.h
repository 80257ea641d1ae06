// host/viewer/render_target.h: an off-screen framebuffer (colour and depth, optionally
// multisampled and resolved) that frames are drawn into and read back from.
#pragma once

#include "host/viewer/image.h"
#include "rubble/error.h"

namespace rubble::viewer {

/// A framebuffer object of a fixed size. Needs the current context for its whole life.
class RenderTarget {
  public:
    /// width x height pixels; `samples` > 1 multisamples (clamped to what the driver allows).
    /// Errors: Device when the framebuffer is incomplete.
    static Result<RenderTarget> create(int width, int height, int samples);

    RenderTarget(RenderTarget&&) noexcept;
    RenderTarget& operator=(RenderTarget&&) noexcept;
    RenderTarget(const RenderTarget&) = delete;
    ~RenderTarget();

    /// Binds the framebuffer for drawing.
    void bind() const;
    /// Resolves the samples and reads the picture back, top row first.
    Image read() const;
    /// Reads the pixels of the bound framebuffer's colour buffer (a window's back buffer).
    static Image readBound(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }

  private:
    RenderTarget() = default;
    void release();
    int width_ = 0, height_ = 0;
    unsigned draw_ = 0, resolve_ = 0; // framebuffers; resolve_ only when multisampled
    unsigned colour_ = 0, depth_ = 0, resolvedColour_ = 0; // renderbuffers
};

} // namespace rubble::viewer
