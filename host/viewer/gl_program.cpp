// host/viewer/gl_program.cpp: shader compilation with the driver's log on failure.
#include "host/viewer/gl_program.h"

#include <vector>

namespace rubble::viewer {
namespace {

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(std::size_t(std::max(length, 1)));
    glGetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    return log.data();
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(std::size_t(std::max(length, 1)));
    glGetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
    return log.data();
}

Result<GLuint> compile(GLenum stage, const char* source, const std::string& name) {
    const GLuint shader = glCreateShader(stage);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = shaderLog(shader);
        glDeleteShader(shader);
        return makeError(ErrorKind::Device, "glCompileShader (" + name + ")", log);
    }
    return shader;
}

} // namespace

Result<GlProgram> GlProgram::create(const std::string& name, const char* vertexSource,
                                    const char* fragmentSource) {
    Result<GLuint> vs = compile(GL_VERTEX_SHADER, vertexSource, name + ".vert");
    if (!vs) return vs.error();
    Result<GLuint> fs = compile(GL_FRAGMENT_SHADER, fragmentSource, name + ".frag");
    if (!fs) {
        glDeleteShader(*vs);
        return fs.error();
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, *vs);
    glAttachShader(program, *fs);
    glLinkProgram(program);
    glDeleteShader(*vs);
    glDeleteShader(*fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = programLog(program);
        glDeleteProgram(program);
        return makeError(ErrorKind::Device, "glLinkProgram (" + name + ")", log);
    }
    return GlProgram(program);
}

GlProgram& GlProgram::operator=(GlProgram&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteProgram(id_);
        id_ = o.id_;
        o.id_ = 0;
    }
    return *this;
}

GlProgram::~GlProgram() {
    if (id_) glDeleteProgram(id_);
}

Status checkGl(const char* what) {
    GLenum first = glGetError();
    if (first == GL_NO_ERROR) return {};
    while (glGetError() != GL_NO_ERROR) {
    }
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(first));
    return makeError(ErrorKind::Device, what, std::string("OpenGL error ") + code);
}

} // namespace rubble::viewer
