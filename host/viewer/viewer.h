// host/viewer/viewer.h: what `rubble view` and `rubble render` ask of the viewer library. Plain
// settings only: this header is included by the command whether or not the viewer is built.
#pragma once

#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"

namespace rubble::viewer {

/// Which kind of off-screen context `rubble render` makes.
enum class ContextKind {
    Auto, ///< EGL, then X11 (starting Xvfb when there is no DISPLAY)
    Egl,  ///< EGL only
    X11,  ///< a hidden GLFW window only
};

/// A camera given on the command line: from `eye` looking at `target`, world frame, m.
struct CameraSpec {
    glm::vec3 eye{0.0f};
    glm::vec3 target{0.0f};
};

/// Debug overlays and colouring, shared by both commands.
struct OverlaySettings {
    bool colourByState = false;
    bool contacts = false, normals = false, aabbs = false, joints = false;
    bool stats = false; ///< the status and per-stage timing lines
};

/// `rubble render`.
struct RenderSettings {
    std::string out;    ///< FILE.png (one frame), DIR/ (numbered PNGs) or FILE.mp4 (ffmpeg)
    std::string replay; ///< a recorded trajectory to draw instead of simulating
    int frames = 1;     ///< pictures to make
    int every = 1;      ///< steps between pictures
    int start = 0;      ///< steps before the first picture
    int width = 640, height = 360;
    int samples = 4;                  ///< multisampling; 1 turns it off
    int fps = 30;                     ///< video frame rate
    std::optional<CameraSpec> camera; ///< else framed automatically from the scene's bounds
    ContextKind context = ContextKind::Auto;
    OverlaySettings overlays;
    bool quiet = false;
};

/// `rubble view`.
struct ViewSettings {
    std::string replay;
    int width = 1280, height = 720;
    std::optional<CameraSpec> camera;
    OverlaySettings overlays;
    int stepsPerFrame = 1;
    int frames = 0;         ///< > 0: quit by itself after that many frames (scripted runs)
    std::string screenshot; ///< PNG of the last frame, written when the viewer quits
    bool paused = false;    ///< start paused
};

/// Renders a scene (simulated, or a replay) to PNG files or a video. Errors: BadInput for bad
/// settings, NotSupported when video is asked for and ffmpeg is missing, Device when no
/// OpenGL context can be made, Io for files, Numerical when the simulation blows up (the
/// pictures before that step are kept).
Status renderScene(const Scene& scene, const RunOptions& run, const RenderSettings& settings);

/// Opens a window on the scene and runs until it is closed (or for `frames` frames).
/// Errors as renderScene, and Device when no window can be opened (no display).
Status viewScene(const Scene& scene, const RunOptions& run, const ViewSettings& settings);

/// Parses `auto`, `egl` or `x11`.
std::optional<ContextKind> parseContextKind(const std::string& s);

} // namespace rubble::viewer
