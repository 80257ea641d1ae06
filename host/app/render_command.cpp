// host/app/render_command.cpp: `rubble render SCENE --out FILE.png|DIR/|FILE.mp4`: off-screen
// pictures of a scene or a recording (or a clear refusal when the build has no viewer).
#include <CLI/CLI.hpp>

#include "host/app/viewer_commands.h"

namespace rubble::app {

void addRenderOptions(CLI::App* cmd, RenderArgs& a) {
    PictureArgs& c = a.common;
    cmd->add_option("scene", c.scene, "Scene file (JSON)")->required();
    cmd->add_option("--out", a.out, "FILE.png (one frame), DIR/ (numbered PNGs) or FILE.mp4")
        ->required();
    cmd->add_option("--replay", c.replay, "Draw a trajectory written by `rubble run --out`");
    cmd->add_option("--camera", c.camera,
                    "eye_x,eye_y,eye_z,target_x,target_y,target_z in m (default: frame the scene)");
    cmd->add_option("--size", c.size, "Picture size WxH in px (default 640x360)");
    cmd->add_option("--frames", a.frames, "Number of pictures (default 1)");
    cmd->add_option("--every", a.every, "Simulation steps between pictures (default 1)");
    cmd->add_option("--start", a.start, "Steps before the first picture (default 0)");
    cmd->add_option("--fps", a.fps, "Frame rate of a video (default 30)");
    cmd->add_option("--samples", a.samples, "Multisampling, 1 for none (default 4)");
    cmd->add_option("--gl", a.context, "auto, egl or x11 (a hidden window; starts Xvfb if needed)");
    cmd->add_flag("--colour-by-state", c.colourByState,
                  "Colour bodies by state (asleep, debris, in contact) instead of one each");
    cmd->add_flag("--contacts", c.contacts, "Show contact points");
    cmd->add_flag("--normals", c.normals, "Show contact normals");
    cmd->add_flag("--aabbs", c.aabbs, "Show each body's bounding box");
    cmd->add_flag("--joints", c.joints, "Show joint anchors and axes");
    cmd->add_flag("--stats", c.stats, "Draw the status and per-stage timing lines");
    cmd->add_flag("--quiet", a.quiet, "Print nothing on success");
}

int renderCommand(const RenderArgs& args) {
    viewer::RenderSettings s;
    Scene scene;
    if (Status st = preparePicture(args.common, scene, s.overlays, s.camera, s.width, s.height);
        !st)
        return report(st.error());
    s.out = args.out;
    s.replay = args.common.replay;
    s.frames = args.frames;
    s.every = args.every;
    s.start = args.start;
    s.samples = args.samples;
    s.fps = args.fps;
    s.quiet = args.quiet;
#ifdef RUBBLE_HAS_VIEWER
    const std::optional<viewer::ContextKind> kind = viewer::parseContextKind(args.context);
    if (!kind)
        return report(
            makeError(ErrorKind::BadInput, "--gl",
                      "unknown value \"" + args.context + "\" (expected auto, egl or x11)"));
    s.context = *kind;
    if (Status st = viewer::renderScene(scene, args.common.run, s); !st) return report(st.error());
    return kExitOk;
#else
    return report(makeError(ErrorKind::NotSupported, "rubble render",
                            "this build has no viewer (configured with RUBBLE_BUILD_VIEWER=OFF)"));
#endif
}

} // namespace rubble::app
