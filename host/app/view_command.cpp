// host/app/view_command.cpp: `rubble view SCENE`: options, checks, and the hand-over to the
// viewer library (or a clear refusal when the build has none).
#include <charconv>
#include <cstdio>

#include <CLI/CLI.hpp>

#include "host/app/viewer_commands.h"

namespace rubble::app {
namespace {

void addCommonOptions(CLI::App* cmd, PictureArgs& a) {
    cmd->add_option("scene", a.scene, "Scene file (JSON)")->required();
    cmd->add_option("--replay", a.replay,
                    "Play back a trajectory written by `rubble run --out` (.csv or .jsonl)");
    cmd->add_option("--camera", a.camera,
                    "eye_x,eye_y,eye_z,target_x,target_y,target_z in m (default: frame the scene)");
    cmd->add_flag("--colour-by-state", a.colourByState,
                  "Colour bodies by state (asleep, debris, in contact) instead of one each");
    cmd->add_flag("--contacts", a.contacts, "Show contact points");
    cmd->add_flag("--normals", a.normals, "Show contact normals");
    cmd->add_flag("--aabbs", a.aabbs, "Show each body's bounding box");
    cmd->add_flag("--joints", a.joints, "Show joint anchors and axes");
}

// Six comma-separated finite numbers.
Result<viewer::CameraSpec> parseCamera(const std::string& text) {
    float v[6];
    std::size_t start = 0;
    for (int k = 0; k < 6; ++k) {
        const std::size_t comma = text.find(',', start);
        const bool last = k == 5;
        if ((comma == std::string::npos) != last)
            return makeError(ErrorKind::BadInput, "--camera",
                             "expected six numbers eye_x,eye_y,eye_z,target_x,target_y,target_z, "
                             "got \"" +
                                 text + "\"");
        const std::string_view field(text.data() + start, (last ? text.size() : comma) - start);
        const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), v[k]);
        if (ec != std::errc() || ptr != field.data() + field.size() || !std::isfinite(v[k]))
            return makeError(ErrorKind::BadInput, "--camera",
                             "\"" + std::string(field) + "\" is not a finite number");
        start = comma + 1;
    }
    viewer::CameraSpec c{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
    if (glm::length(c.eye - c.target) < 1e-4f)
        return makeError(ErrorKind::BadInput, "--camera",
                         "the eye and the target are the same point");
    return c;
}

Status parseSize(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find_first_of("xX");
    const auto number = [](std::string_view s, int& out) {
        const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
        return ec == std::errc() && ptr == s.data() + s.size() && !s.empty();
    };
    if (x == std::string::npos || !number(std::string_view(text).substr(0, x), width) ||
        !number(std::string_view(text).substr(x + 1), height) || width < 16 || height < 16 ||
        width > 8192 || height > 8192)
        return makeError(ErrorKind::BadInput, "--size",
                         "expected WxH with each side from 16 to 8192 px, got \"" + text + "\"");
    return {};
}

} // namespace

void addViewOptions(CLI::App* cmd, ViewArgs& a) {
    addCommonOptions(cmd, a.common);
    cmd->add_option("--size", a.common.size, "Window size WxH in px (default 1280x720)");
    cmd->add_option("--frames", a.frames, "Quit by itself after N frames (scripted runs)");
    cmd->add_option("--screenshot", a.screenshot, "Write the last frame to this PNG on quitting");
    cmd->add_option("--steps-per-frame", a.stepsPerFrame, "Simulation steps per drawn frame");
    cmd->add_flag("--paused", a.paused, "Start paused");
}

Status preparePicture(const PictureArgs& a, Scene& scene, viewer::OverlaySettings& overlays,
                      std::optional<viewer::CameraSpec>& camera, int& width, int& height) {
    Result<Scene> loaded = loadScene(a.scene);
    if (!loaded) return loaded.error();
    scene = std::move(*loaded);
    RUBBLE_TRY(applyOverrides(a.overrides, scene));
    if (!a.camera.empty()) {
        Result<viewer::CameraSpec> c = parseCamera(a.camera);
        if (!c) return c.error();
        camera = *c;
    }
    if (!a.size.empty()) RUBBLE_TRY(parseSize(a.size, width, height));
    overlays.colourByState = a.colourByState;
    overlays.contacts = a.contacts;
    overlays.normals = a.normals;
    overlays.aabbs = a.aabbs;
    overlays.joints = a.joints;
    overlays.stats = a.stats;
    return {};
}

int viewCommand(const ViewArgs& args) {
    viewer::ViewSettings s;
    Scene scene;
    if (Status st = preparePicture(args.common, scene, s.overlays, s.camera, s.width, s.height);
        !st)
        return report(st.error());
    s.replay = args.common.replay;
    s.frames = args.frames;
    s.screenshot = args.screenshot;
    s.stepsPerFrame = args.stepsPerFrame;
    s.paused = args.paused;
#ifdef RUBBLE_HAS_VIEWER
    if (Status st = viewer::viewScene(scene, args.common.run, s); !st) return report(st.error());
    return kExitOk;
#else
    return report(makeError(ErrorKind::NotSupported, "rubble view",
                            "this build has no viewer (configured with RUBBLE_BUILD_VIEWER=OFF)"));
#endif
}

} // namespace rubble::app
