// host/viewer/gl_program.h: GLSL programs compiled and linked, and the GL calls' error checks.
#pragma once

#include <string>

#include <epoxy/gl.h>

#include "rubble/error.h"

namespace rubble::viewer {

/// A linked program; deletes itself. Needs a current context for its whole life.
class GlProgram {
  public:
    /// Compiles and links; Device error at `glCompileShader (name)` or `glLinkProgram (name)`
    /// carrying the driver's log.
    static Result<GlProgram> create(const std::string& name, const char* vertexSource,
                                    const char* fragmentSource);

    GlProgram() = default;
    GlProgram(GlProgram&& o) noexcept : id_(o.id_) { o.id_ = 0; }
    GlProgram& operator=(GlProgram&& o) noexcept;
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;
    ~GlProgram();

    GLuint id() const { return id_; }
    GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

  private:
    explicit GlProgram(GLuint id) : id_(id) {}
    GLuint id_ = 0;
};

/// Device error naming `what` when glGetError reports one; clears the error flags.
Status checkGl(const char* what);

} // namespace rubble::viewer
