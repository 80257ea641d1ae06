// host/app/viewer_commands.h: `rubble view` and `rubble render`, filled by CLI11 in main.cpp;
// both say so and exit 2 when the build has no viewer (RUBBLE_BUILD_VIEWER=OFF).
#pragma once

#include <string>

#include "host/app/commands.h"
#include "host/viewer/viewer.h"

namespace CLI {
class App;
}

namespace rubble::app {

/// The options both commands share, as text until checked.
struct PictureArgs {
    std::string scene;
    Overrides overrides;
    RunOptions run;
    std::string replay;
    std::string camera; ///< eye_x,eye_y,eye_z,target_x,target_y,target_z
    std::string size;   ///< WxH
    bool colourByState = false, contacts = false, normals = false, aabbs = false, joints = false;
    bool stats = false;
};

struct ViewArgs {
    PictureArgs common;
    int frames = 0;
    std::string screenshot;
    int stepsPerFrame = 1;
    bool paused = false;
};
int viewCommand(const ViewArgs& args);

struct RenderArgs {
    PictureArgs common;
    std::string out;
    int frames = 1, every = 1, start = 0, samples = 4, fps = 30;
    std::string context = "auto";
    bool quiet = false;
};
int renderCommand(const RenderArgs& args);

/// Adds the options of `view` (scene, replay, camera, overlays, scripted frames) to a command.
void addViewOptions(CLI::App* cmd, ViewArgs& a);
/// Adds the options of `render` (scene, replay, camera, overlays, output and frames).
void addRenderOptions(CLI::App* cmd, RenderArgs& a);

/// Loads the scene, applies the overrides and checks the camera and size options into the
/// viewer's settings. Errors: BadInput naming the file or the option.
Status preparePicture(const PictureArgs& a, Scene& scene, viewer::OverlaySettings& overlays,
                      std::optional<viewer::CameraSpec>& camera, int& width, int& height);

} // namespace rubble::app
