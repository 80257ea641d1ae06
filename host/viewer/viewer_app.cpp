// host/viewer/viewer_app.cpp: `rubble view`: a GLFW window on a live world or a recording, with
// mouse camera controls, keys for stepping, resetting, switching backend and the overlays.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "host/core/math.h"
#include "host/viewer/render_target.h"
#include "host/viewer/renderer.h"
#include "host/viewer/replay.h"
#include "host/viewer/scene_view.h"
#include "host/viewer/viewer.h"
#include "rubble/world.h"

namespace rubble::viewer {
namespace {

constexpr double kMessageSeconds = 6.0; // how long a notice stays on screen
constexpr float kZoomPerNotch = 0.88f;
constexpr const char* kHelp = "drag: orbit  right/shift-drag: pan  wheel: zoom  space: pause  "
                              ".: step  r: reset  b: backend  c: contacts  n: normals  "
                              "a: AABBs  j: joints  p: particles  m: colours  f: frame  "
                              "s: screenshot  t: figures  h: help  q: quit";

// The scene with each body moved to where `world` has it now and the step's time taken off the
// events still to come, so that a world built from it carries on from here.
Scene sceneFromNow(const Scene& original, const World& world) {
    Scene s = original;
    for (std::uint32_t i = 0; i < world.bodyCount() && i < s.bodies.size(); ++i) {
        const BodyState b = world.body(i);
        BodyDesc& d = s.bodies[i];
        d.position = b.position;
        d.orientation = b.orientation;
        d.linearVelocity = b.linearVelocity;
        d.angularVelocity = b.angularVelocity;
    }
    // Joint anchors and axes are given at the initial pose: carry them with body a.
    for (JointDesc& j : s.joints) {
        const BodyDesc& a0 = original.bodies[j.a];
        const glm::quat q0 = glm::normalize(a0.orientation);
        const glm::vec3 anchorInA = glm::inverse(q0) * (j.anchor - a0.position);
        const glm::vec3 axisInA = glm::inverse(q0) * j.axis;
        j.anchor = s.bodies[j.a].position + s.bodies[j.a].orientation * anchorInA;
        j.axis = s.bodies[j.a].orientation * axisInA;
    }
    const float now = float(world.time());
    s.events.clear();
    for (EventDesc e : original.events)
        if (e.time >= now) {
            e.time -= now;
            s.events.push_back(e);
        }
    return s;
}

class ViewerApp {
  public:
    ViewerApp(const Scene& scene, const RunOptions& run, const ViewSettings& settings)
        : scene_(scene), run_(run), settings_(settings), overlays_(toOverlays(settings.overlays)),
          paused_(settings.paused), showStats_(true) {}

    ~ViewerApp() {
        view_.reset();
        renderer_.reset(); // GL objects go before their context
        if (window_) glfwDestroyWindow(window_);
        if (glfwStarted_) glfwTerminate();
    }

    Status start() {
        Result<World> world = World::create(scene_, run_);
        if (!world) return world.error();
        world_.emplace(std::move(*world));
        backend_ = world_->options().backend;
        if (!settings_.replay.empty()) {
            Result<Replay> r = Replay::load(settings_.replay, *world_);
            if (!r) return r.error();
            replay_.emplace(std::move(*r));
        }
        RUBBLE_TRY(openWindow());
        Result<Renderer> renderer = Renderer::create(world_->shapes());
        if (!renderer) return renderer.error();
        renderer_.emplace(std::move(*renderer));
        view_.emplace(*world_);
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_, &w, &h);
        camera_ = initialCamera(settings_.camera, *view_, float(w) / float(std::max(h, 1)));
        return {};
    }

    Status run() {
        int frame = 0;
        while (!glfwWindowShouldClose(window_)) {
            glfwPollEvents();
            if (Status s = advance(); !s) return s;
            int w = 0, h = 0;
            glfwGetFramebufferSize(window_, &w, &h);
            if (w > 0 && h > 0) {
                renderer_->setTextScale(h >= 600 ? 2.0f : 1.0f);
                buildFrame();
                glBindFramebuffer(GL_FRAMEBUFFER, 0);
                renderer_->draw(draw_, camera_, w, h);
            }
            ++frame;
            const bool last = settings_.frames > 0 && frame >= settings_.frames;
            if ((last && !settings_.screenshot.empty()) || screenshotRequested_) {
                RUBBLE_TRY(screenshot(w, h, last ? settings_.screenshot : ""));
                screenshotRequested_ = false;
            }
            glfwSwapBuffers(window_);
            if (last) break;
        }
        return {};
    }

  private:
    Status openWindow() {
        const char* display = std::getenv("DISPLAY");
        const char* wayland = std::getenv("WAYLAND_DISPLAY");
        if ((!display || !*display) && (!wayland || !*wayland))
            return makeError(ErrorKind::Device, "rubble view",
                             "no display (DISPLAY is not set): run it under xvfb-run for a "
                             "scripted run, or use `rubble render` for pictures");
        if (!glfwInit()) return glfwError("glfwInit");
        glfwStarted_ = true;
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_SAMPLES, settings_.frames > 0 ? 0 : 4);
        const std::string title = "rubble: " + world_->sceneName();
        window_ =
            glfwCreateWindow(settings_.width, settings_.height, title.c_str(), nullptr, nullptr);
        if (!window_) return glfwError("glfwCreateWindow (OpenGL 3.3 core)");
        glfwMakeContextCurrent(window_);
        // A scripted run goes as fast as it can; a person gets the display's rate.
        glfwSwapInterval(settings_.frames > 0 ? 0 : 1);
        glfwSetWindowUserPointer(window_, this);
        glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
            if (action == GLFW_PRESS || action == GLFW_REPEAT) self(w)->onKey(key, mods);
        });
        glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int mods) {
            self(w)->onButton(button, action, mods);
        });
        glfwSetCursorPosCallback(
            window_, [](GLFWwindow* w, double x, double y) { self(w)->onCursor(x, y); });
        glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) {
            self(w)->camera_.zoom(std::pow(kZoomPerNotch, float(dy)));
        });
        return {};
    }

    static ViewerApp* self(GLFWwindow* w) {
        return static_cast<ViewerApp*>(glfwGetWindowUserPointer(w));
    }

    static Error glfwError(const char* call) {
        const char* message = nullptr;
        glfwGetError(&message);
        return makeError(ErrorKind::Device, call, message ? message : "failed");
    }

    void notify(const std::string& text) {
        message_ = text;
        messageUntil_ = glfwGetTime() + kMessageSeconds;
        std::fprintf(stderr, "rubble view: %s\n", text.c_str());
    }

    void onKey(int key, int mods) {
        switch (key) {
        case GLFW_KEY_ESCAPE:
        case GLFW_KEY_Q:
            glfwSetWindowShouldClose(window_, GLFW_TRUE);
            break;
        case GLFW_KEY_SPACE:
            paused_ = !paused_;
            break;
        case GLFW_KEY_PERIOD:
            paused_ = true;
            stepOnce_ = true;
            break;
        case GLFW_KEY_R:
            reset();
            break;
        case GLFW_KEY_B:
            switchBackend();
            break;
        case GLFW_KEY_C:
            overlays_.contacts = !overlays_.contacts;
            break;
        case GLFW_KEY_N:
            overlays_.normals = !overlays_.normals;
            break;
        case GLFW_KEY_A:
            overlays_.aabbs = !overlays_.aabbs;
            break;
        case GLFW_KEY_J:
            overlays_.joints = !overlays_.joints;
            if (overlays_.joints && world_->joints().empty())
                notify("this scene has no joints");
            break;
        case GLFW_KEY_P:
            overlays_.particles = !overlays_.particles;
            if (overlays_.particles) notify("particles: this world keeps none to show");
            break;
        case GLFW_KEY_M:
            overlays_.colours =
                overlays_.colours == ColourMode::Body ? ColourMode::State : ColourMode::Body;
            break;
        case GLFW_KEY_F: {
            int w = 0, h = 0;
            glfwGetFramebufferSize(window_, &w, &h);
            camera_ = Camera::framing(view_->bounds(), float(w) / float(std::max(h, 1)));
            break;
        }
        case GLFW_KEY_S:
            screenshotRequested_ = true;
            break;
        case GLFW_KEY_T:
            showStats_ = !showStats_;
            break;
        case GLFW_KEY_H:
            showHelp_ = !showHelp_;
            break;
        default:
            break;
        }
        (void)mods;
    }

    void onButton(int button, int action, int mods) {
        const bool down = action == GLFW_PRESS;
        if (button == GLFW_MOUSE_BUTTON_LEFT) {
            dragOrbit_ = down && !(mods & GLFW_MOD_SHIFT);
            dragPan_ = down && (mods & GLFW_MOD_SHIFT);
        } else if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE) {
            dragPan_ = down;
        }
        if (!down) dragOrbit_ = dragPan_ = false;
    }

    void onCursor(double x, double y) {
        const float dx = float(x - cursorX_), dy = float(y - cursorY_);
        cursorX_ = x;
        cursorY_ = y;
        if (dragOrbit_) camera_.orbit(dx, dy);
        if (dragPan_) {
            int w = 0, h = 0;
            glfwGetFramebufferSize(window_, &w, &h);
            camera_.pan(dx, dy, h);
        }
    }

    void reset() {
        if (replay_) {
            replayIndex_ = 0;
            return;
        }
        Scene s = scene_;
        s.simulation.backend = backend_;
        Result<World> world = World::create(s, run_);
        if (!world) {
            notify("reset: " + world.error().describe());
            return;
        }
        world_.emplace(std::move(*world));
        view_.emplace(*world_);
        stepOffset_ = 0;
        timeOffset_ = 0.0;
    }

    void switchBackend() {
        if (replay_) {
            notify("a replay has no backend to switch");
            return;
        }
        const Backend next = backend_ == Backend::Cpu ? Backend::OpenCl : Backend::Cpu;
        Scene s = sceneFromNow(scene_, *world_);
        s.simulation.backend = next;
        Result<World> world = World::create(s, run_);
        if (!world) {
            notify(std::string(toString(next)) + ": " + world.error().describe() + "; staying on " +
                   std::string(toString(backend_)));
            return;
        }
        stepOffset_ += world_->stepIndex();
        timeOffset_ += world_->time();
        world_.emplace(std::move(*world));
        view_.emplace(*world_);
        backend_ = next;
        notify("backend " + std::string(toString(next)) + " (" + world_->deviceName() + ")");
    }

    Status advance() {
        if (paused_ && !stepOnce_) return {};
        const bool once = stepOnce_;
        stepOnce_ = false;
        if (replay_) {
            const std::size_t last = replay_->frames().size() - 1;
            replayIndex_ =
                std::min(replayIndex_ + (once ? 1 : std::size_t(settings_.stepsPerFrame)), last);
            return {};
        }
        const int steps = once ? 1 : settings_.stepsPerFrame;
        for (int i = 0; i < steps; ++i) {
            if (Status s = world_->step(); !s) {
                // A blown-up world stays on screen, paused, with the reason.
                paused_ = true;
                notify(s.error().describe());
                if (settings_.frames > 0) return s;
                break;
            }
        }
        return {};
    }

    void buildFrame() {
        if (replay_) {
            const ReplayFrame& f = replay_->frames()[replayIndex_];
            view_->build(f.poses, nullptr, overlays_, draw_);
            if (showStats_)
                draw_.text.push_back(replayLine(f.step, f.time, *world_, replay_->path()));
        } else {
            currentPoses(*world_, poses_);
            view_->build(poses_, &*world_, overlays_, draw_);
            if (showStats_) {
                draw_.text.push_back(statusLine(
                    stepOffset_ + world_->stepIndex(), timeOffset_ + world_->time(),
                    *world_, std::string(toString(backend_)), world_->deviceName()));
                draw_.text.push_back(stageLine(world_->lastStep()));
            }
        }
        if (paused_) draw_.text.push_back("paused");
        if (showHelp_)
            draw_.text.push_back(kHelp);
        else if (showStats_)
            draw_.text.push_back("h: help");
        if (!message_.empty() && glfwGetTime() < messageUntil_) draw_.message = message_;
    }

    Status screenshot(int w, int h, const std::string& path) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        const Image image = RenderTarget::readBound(w, h);
        std::string file = path;
        if (file.empty()) file = "rubble_screenshot_" + std::to_string(screenshots_++) + ".png";
        RUBBLE_TRY(writePng(file, image));
        if (path.empty()) notify("wrote " + file);
        return {};
    }

    Scene scene_;
    RunOptions run_;
    ViewSettings settings_;
    Overlays overlays_;
    std::optional<World> world_;
    std::optional<Replay> replay_;
    std::optional<Renderer> renderer_;
    std::optional<SceneView> view_;
    Camera camera_;
    DrawList draw_;
    std::vector<BodyPose> poses_;
    GLFWwindow* window_ = nullptr;
    bool glfwStarted_ = false;
    Backend backend_ = Backend::Cpu;
    std::int64_t stepOffset_ = 0;
    double timeOffset_ = 0.0;
    std::size_t replayIndex_ = 0;
    bool paused_ = false, stepOnce_ = false, showStats_ = true, showHelp_ = false;
    bool screenshotRequested_ = false;
    int screenshots_ = 0;
    bool dragOrbit_ = false, dragPan_ = false;
    double cursorX_ = 0.0, cursorY_ = 0.0;
    std::string message_;
    double messageUntil_ = 0.0;
};

} // namespace

Status viewScene(const Scene& scene, const RunOptions& run, const ViewSettings& settings) {
    if (settings.width < 16 || settings.height < 16)
        return makeError(ErrorKind::BadInput, "--size", "must be WxH with each side 16 or more");
    if (settings.stepsPerFrame < 1)
        return makeError(ErrorKind::BadInput, "--steps-per-frame", "must be 1 or more");
    if (settings.frames < 0) return makeError(ErrorKind::BadInput, "--frames", "must be 0 or more");
    ViewerApp app(scene, run, settings);
    RUBBLE_TRY(app.start());
    return app.run();
}

} // namespace rubble::viewer
