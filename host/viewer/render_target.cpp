// host/viewer/render_target.cpp: framebuffer objects and pixel read-back.
#include "host/viewer/render_target.h"

#include <algorithm>
#include <cstring>

#include <epoxy/gl.h>

namespace rubble::viewer {
namespace {

GLuint makeRenderbuffer(GLenum format, int width, int height, int samples) {
    GLuint rb = 0;
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    if (samples > 1)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, width, height);
    else
        glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    return rb;
}

} // namespace

Result<RenderTarget> RenderTarget::create(int width, int height, int samples) {
    RenderTarget t;
    t.width_ = width;
    t.height_ = height;
    GLint maxSamples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    samples = std::clamp(samples, 1, std::max(1, int(maxSamples)));

    glGenFramebuffers(1, &t.draw_);
    glBindFramebuffer(GL_FRAMEBUFFER, t.draw_);
    t.colour_ = makeRenderbuffer(GL_RGBA8, width, height, samples);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.colour_);
    t.depth_ = makeRenderbuffer(GL_DEPTH24_STENCIL8, width, height, samples);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                              t.depth_);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return makeError(ErrorKind::Device, "glCheckFramebufferStatus",
                         "the " + std::to_string(width) + "x" + std::to_string(height) +
                             " framebuffer is incomplete");
    if (samples > 1) {
        glGenFramebuffers(1, &t.resolve_);
        glBindFramebuffer(GL_FRAMEBUFFER, t.resolve_);
        t.resolvedColour_ = makeRenderbuffer(GL_RGBA8, width, height, 1);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  t.resolvedColour_);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            return makeError(ErrorKind::Device, "glCheckFramebufferStatus",
                             "the resolve framebuffer is incomplete");
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return t;
}

RenderTarget::RenderTarget(RenderTarget&& o) noexcept {
    *this = std::move(o);
}

RenderTarget& RenderTarget::operator=(RenderTarget&& o) noexcept {
    if (this == &o) return *this;
    release();
    width_ = o.width_;
    height_ = o.height_;
    draw_ = std::exchange(o.draw_, 0);
    resolve_ = std::exchange(o.resolve_, 0);
    colour_ = std::exchange(o.colour_, 0);
    depth_ = std::exchange(o.depth_, 0);
    resolvedColour_ = std::exchange(o.resolvedColour_, 0);
    return *this;
}

RenderTarget::~RenderTarget() {
    release();
}

void RenderTarget::release() {
    const GLuint framebuffers[] = {draw_, resolve_};
    const GLuint renderbuffers[] = {colour_, depth_, resolvedColour_};
    if (draw_) glDeleteFramebuffers(2, framebuffers);
    if (colour_) glDeleteRenderbuffers(3, renderbuffers);
    draw_ = resolve_ = colour_ = depth_ = resolvedColour_ = 0;
}

void RenderTarget::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, draw_);
}

Image RenderTarget::read() const {
    if (resolve_) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_);
        glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, resolve_);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, draw_);
    }
    Image image = readBound(width_, height_);
    glBindFramebuffer(GL_FRAMEBUFFER, draw_);
    return image;
}

Image RenderTarget::readBound(int width, int height) {
    Image image;
    image.width = width;
    image.height = height;
    image.rgb.resize(std::size_t(width) * std::size_t(height) * 3);
    std::vector<std::uint8_t> bottomUp(image.rgb.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, bottomUp.data());
    // GL's first row is the bottom one; pictures start at the top.
    const std::size_t row = std::size_t(width) * 3;
    for (int y = 0; y < height; ++y)
        std::memcpy(&image.rgb[std::size_t(y) * row], &bottomUp[std::size_t(height - 1 - y) * row],
                    row);
    return image;
}

} // namespace rubble::viewer
