// host/viewer/frame_output.h: where rendered frames go: one PNG, a folder of numbered PNGs, or
// a video encoded by an ffmpeg child process fed raw frames on a pipe.
#pragma once

#include <sys/types.h>

#include <string>

#include "host/viewer/image.h"
#include "rubble/error.h"

namespace rubble::viewer {

/// A destination for frames, chosen by the form of `--out`. Move-only.
class FrameOutput {
  public:
    enum class Kind { Png, Folder, Video };

    /// `FILE.png` takes one frame; `DIR/` (or an existing folder) takes numbered
    /// `frame_00000.png` files and is created when missing; `FILE.mp4`, `.mkv`, `.webm` or
    /// `.mov` starts ffmpeg. Errors: BadInput naming `--out` (another extension, a PNG asked to
    /// hold several frames), NotSupported when video is asked for and ffmpeg is not on PATH,
    /// Io when the folder cannot be made or ffmpeg cannot start.
    static Result<FrameOutput> open(const std::string& out, int frames, int width, int height,
                                    int fps);

    FrameOutput(FrameOutput&& o) noexcept;
    FrameOutput& operator=(FrameOutput&&) = delete;
    FrameOutput(const FrameOutput&) = delete;
    ~FrameOutput();

    /// Writes the next frame. Errors: Io naming the file, or ffmpeg's exit.
    Status write(const Image& frame);
    /// Closes the video (waiting for ffmpeg) or does nothing. Errors: Io when ffmpeg failed.
    Status finish();

    Kind kind() const { return kind_; }
    int written() const { return written_; }
    /// The file or folder written, for messages.
    const std::string& path() const { return path_; }

  private:
    FrameOutput(Kind kind, std::string path) : kind_(kind), path_(std::move(path)) {}
    Kind kind_;
    std::string path_;
    int written_ = 0;
    pid_t ffmpeg_ = -1;
    int pipe_ = -1;
};

} // namespace rubble::viewer
