// host/viewer/replay.h: a recorded trajectory (`rubble run --out FILE.csv|FILE.jsonl`) read back
// as the poses of a scene's bodies at each written step, matched by body name.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rubble/error.h"
#include "rubble/shared/body.h"
#include "rubble/world.h"

namespace rubble::viewer {

using shared::BodyPose;

/// One written step: every body's pose, by the scene's body index. A body the file leaves out
/// of a step keeps its pose from the step before (from the scene at the start).
struct ReplayFrame {
    std::int64_t step = 0;
    double time = 0.0; ///< s
    std::vector<BodyPose> poses;
};

/// All the steps of a recording.
class Replay {
  public:
    /// Reads `path` (.csv or .jsonl, SCENE_FORMAT.md Outputs) against the bodies of `world`
    /// (names and initial poses). Errors: BadInput at `path:line` for a malformed row, a body
    /// the scene does not have, a non-finite number or a step that goes backwards; at `path`
    /// for a missing, unreadable or empty file or another extension.
    static Result<Replay> load(const std::string& path, const World& world);

    const std::vector<ReplayFrame>& frames() const { return frames_; }
    const std::string& path() const { return path_; }

    /// The last frame whose step is at most `step`; the first frame when all are later.
    const ReplayFrame& atStep(std::int64_t step) const;

  private:
    std::string path_;
    std::vector<ReplayFrame> frames_;
};

} // namespace rubble::viewer
