// host/viewer/offscreen_context.cpp: EGL (surfaceless or pbuffer) and hidden-window contexts.
#include "host/viewer/offscreen_context.h"

#include <cstdlib>
#include <cstring>
#include <optional>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "host/viewer/xvfb_server.h"

namespace rubble::viewer {
namespace {

std::string eglErrorName(EGLint e) {
    switch (e) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
        return "EGL_BAD_SURFACE";
    default: {
        char buf[24];
        std::snprintf(buf, sizeof buf, "EGL error 0x%04x", unsigned(e));
        return buf;
    }
    }
}

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = std::strstr(list, name); p; p = std::strstr(p + n, name))
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

std::string rendererName() {
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return std::string(renderer ? renderer : "?") + ", OpenGL " + (version ? version : "?");
}

// An EGL display, context and (for the pbuffer way) surface.
struct EglHandles {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EGLSurface surface = EGL_NO_SURFACE;

    void release() {
        if (display == EGL_NO_DISPLAY) return;
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
        if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
        eglTerminate(display);
        *this = {};
    }
};

// Initialises `display` and makes a 3.3 core context current on it; `pbuffer` also makes a
// 16 x 16 pbuffer surface (frames go to a framebuffer object either way).
Status makeEglContext(EglHandles& h, bool pbuffer, const std::string& way) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(h.display, &major, &minor))
        return makeError(ErrorKind::Device, way + ": eglInitialize", eglErrorName(eglGetError()));
    if (!eglBindAPI(EGL_OPENGL_API))
        return makeError(ErrorKind::Device, way + ": eglBindAPI", eglErrorName(eglGetError()));
    const EGLint configAttributes[] = {EGL_SURFACE_TYPE, pbuffer ? EGL_PBUFFER_BIT : 0,
                                       EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (!eglChooseConfig(h.display, configAttributes, &config, 1, &count) || count < 1) {
        const bool noConfig =
            hasExtension(eglQueryString(h.display, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
        if (pbuffer || !noConfig)
            return makeError(ErrorKind::Device, way + ": eglChooseConfig",
                             "no configuration renders OpenGL");
        config = nullptr; // EGL_NO_CONFIG_KHR
    }
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        3,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        3,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    h.context = eglCreateContext(h.display, config, EGL_NO_CONTEXT, contextAttributes);
    if (h.context == EGL_NO_CONTEXT)
        return makeError(ErrorKind::Device, way + ": eglCreateContext (OpenGL 3.3 core)",
                         eglErrorName(eglGetError()));
    if (pbuffer) {
        const EGLint surfaceAttributes[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
        h.surface = eglCreatePbufferSurface(h.display, config, surfaceAttributes);
        if (h.surface == EGL_NO_SURFACE)
            return makeError(ErrorKind::Device, way + ": eglCreatePbufferSurface",
                             eglErrorName(eglGetError()));
    }
    if (!eglMakeCurrent(h.display, h.surface, h.surface, h.context))
        return makeError(ErrorKind::Device, way + ": eglMakeCurrent", eglErrorName(eglGetError()));
    return {};
}

} // namespace

struct OffscreenContext::Impl {
    EglHandles egl;
    GLFWwindow* window = nullptr;
    std::optional<XvfbServer> xvfb;
    std::string description;

    ~Impl() {
        egl.release();
        if (window) {
            glfwDestroyWindow(window);
            glfwTerminate();
        }
    }

    Status tryEgl() {
        const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        std::string tried;
        // Mesa's surfaceless platform needs no display server and no GPU.
        if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless") &&
            hasExtension(clientExtensions, "EGL_EXT_platform_base")) {
            egl.display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                   EGL_DEFAULT_DISPLAY, nullptr);
            if (egl.display != EGL_NO_DISPLAY) {
                const Status s = makeEglContext(egl, false, "EGL surfaceless");
                if (s) {
                    description = "EGL surfaceless: " + rendererName();
                    return {};
                }
                tried = s.error().describe() + "; ";
                egl.release();
            }
        }
        // Any other EGL: its default display with a small pbuffer.
        egl.display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        if (egl.display == EGL_NO_DISPLAY)
            return makeError(ErrorKind::Device, "eglGetDisplay", tried + "no default EGL display");
        const Status s = makeEglContext(egl, true, "EGL pbuffer");
        if (!s) {
            egl.release();
            return makeError(ErrorKind::Device, "EGL", tried + s.error().describe());
        }
        description = "EGL pbuffer: " + rendererName();
        return {};
    }

    Status tryX11() {
        const char* display = std::getenv("DISPLAY");
        if (!display || !*display) {
            Result<XvfbServer> server = XvfbServer::start();
            if (!server) return server.error();
            xvfb.emplace(std::move(*server));
            // GLFW 3.3 opens the display named by DISPLAY and offers no other way to name it.
            setenv("DISPLAY", xvfb->display().c_str(), 1);
        }
        if (!glfwInit()) {
            const char* message = nullptr;
            glfwGetError(&message);
            return makeError(ErrorKind::Device, "glfwInit", message ? message : "failed");
        }
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        window = glfwCreateWindow(16, 16, "rubble render", nullptr, nullptr);
        if (!window) {
            const char* message = nullptr;
            glfwGetError(&message);
            glfwTerminate();
            return makeError(ErrorKind::Device, "glfwCreateWindow (OpenGL 3.3 core)",
                             message ? message : "failed");
        }
        glfwMakeContextCurrent(window);
        description =
            std::string(xvfb ? "X11 on Xvfb " + xvfb->display() : "X11") + ": " + rendererName();
        return {};
    }
};

Result<OffscreenContext> OffscreenContext::create(ContextKind kind) {
    auto impl = std::make_unique<Impl>();
    std::string tried;
    if (kind != ContextKind::X11) {
        const Status s = impl->tryEgl();
        if (s) return OffscreenContext(std::move(impl));
        tried = s.error().describe();
        if (kind == ContextKind::Egl) return s.error();
    }
    const Status s = impl->tryX11();
    if (s) return OffscreenContext(std::move(impl));
    return makeError(ErrorKind::Device, "no OpenGL 3.3 context",
                     (tried.empty() ? "" : tried + "; then ") + s.error().describe());
}

OffscreenContext::OffscreenContext(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OffscreenContext::OffscreenContext(OffscreenContext&&) noexcept = default;
OffscreenContext& OffscreenContext::operator=(OffscreenContext&&) noexcept = default;
OffscreenContext::~OffscreenContext() = default;

const std::string& OffscreenContext::description() const {
    return impl_->description;
}

std::optional<ContextKind> parseContextKind(const std::string& s) {
    if (s == "auto") return ContextKind::Auto;
    if (s == "egl") return ContextKind::Egl;
    if (s == "x11") return ContextKind::X11;
    return std::nullopt;
}

} // namespace rubble::viewer
