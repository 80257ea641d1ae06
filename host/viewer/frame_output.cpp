// host/viewer/frame_output.cpp: PNG files and the ffmpeg pipe.
#include "host/viewer/frame_output.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "host/viewer/xvfb_server.h"

namespace rubble::viewer {
namespace {

bool endsWith(const std::string& s, const char* suffix) {
    const std::size_t n = std::strlen(suffix);
    if (s.size() < n) return false;
    for (std::size_t i = 0; i < n; ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i])
            return false;
    return true;
}

bool isVideo(const std::string& out) {
    return endsWith(out, ".mp4") || endsWith(out, ".mkv") || endsWith(out, ".webm") ||
           endsWith(out, ".mov");
}

} // namespace

Result<FrameOutput> FrameOutput::open(const std::string& out, int frames, int width, int height,
                                      int fps) {
    std::error_code ec;
    const bool folder =
        (!out.empty() && out.back() == '/') || std::filesystem::is_directory(out, ec);
    if (folder) {
        std::filesystem::create_directories(out, ec);
        if (ec) return makeError(ErrorKind::Io, out, "cannot create the folder: " + ec.message());
        return FrameOutput(Kind::Folder, out.back() == '/' ? out : out + "/");
    }
    if (endsWith(out, ".png")) {
        if (frames != 1)
            return makeError(ErrorKind::BadInput, "--out " + out,
                             "a .png file holds one frame; use --out DIR/ or --out FILE.mp4 for "
                             "--frames " +
                                 std::to_string(frames));
        return FrameOutput(Kind::Png, out);
    }
    if (!isVideo(out))
        return makeError(ErrorKind::BadInput, "--out " + out,
                         "expected FILE.png, a folder DIR/, or a video FILE.mp4 (.mkv, .webm, "
                         ".mov)");

    const std::string ffmpeg = findOnPath("ffmpeg");
    if (ffmpeg.empty())
        return makeError(ErrorKind::NotSupported, "--out " + out,
                         "video needs ffmpeg, which is not installed (apt-get install ffmpeg); "
                         "--out DIR/ writes the frames as PNG files instead");
    int fds[2];
    if (pipe(fds) != 0) return makeError(ErrorKind::Io, "pipe", std::strerror(errno));
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    const std::string rate = std::to_string(fps);
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return makeError(ErrorKind::Io, "fork", std::strerror(errno));
    }
    if (pid == 0) {
        close(fds[1]);
        dup2(fds[0], STDIN_FILENO);
        close(fds[0]);
        // Even sizes for 4:2:0 chroma; x264 where the container takes it, else ffmpeg's choice.
        std::vector<const char*> args = {"ffmpeg",
                                         "-hide_banner",
                                         "-loglevel",
                                         "error",
                                         "-y",
                                         "-f",
                                         "rawvideo",
                                         "-pixel_format",
                                         "rgb24",
                                         "-video_size",
                                         size.c_str(),
                                         "-framerate",
                                         rate.c_str(),
                                         "-i",
                                         "-",
                                         "-vf",
                                         "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                         "-pix_fmt",
                                         "yuv420p"};
        if (endsWith(out, ".mp4") || endsWith(out, ".mov") || endsWith(out, ".mkv"))
            args.insert(args.end(), {"-c:v", "libx264", "-preset", "medium", "-crf", "20"});
        args.push_back(out.c_str());
        args.push_back(nullptr);
        execv(ffmpeg.c_str(), const_cast<char* const*>(args.data()));
        _exit(127);
    }
    close(fds[0]);
    FrameOutput o(Kind::Video, out);
    o.ffmpeg_ = pid;
    o.pipe_ = fds[1];
    return o;
}

FrameOutput::FrameOutput(FrameOutput&& o) noexcept
    : kind_(o.kind_), path_(std::move(o.path_)), written_(o.written_), ffmpeg_(o.ffmpeg_),
      pipe_(o.pipe_) {
    o.ffmpeg_ = -1;
    o.pipe_ = -1;
}

FrameOutput::~FrameOutput() {
    if (pipe_ >= 0) close(pipe_);
    if (ffmpeg_ > 0) waitpid(ffmpeg_, nullptr, 0);
}

Status FrameOutput::write(const Image& frame) {
    if (kind_ == Kind::Png) {
        RUBBLE_TRY(writePng(path_, frame));
    } else if (kind_ == Kind::Folder) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05d.png", written_);
        RUBBLE_TRY(writePng(path_ + name, frame));
    } else {
        // ffmpeg gone away must be an error here, not a SIGPIPE that ends the command.
        struct sigaction ignore {
        }, previous{};
        ignore.sa_handler = SIG_IGN;
        sigaction(SIGPIPE, &ignore, &previous);
        const std::uint8_t* p = frame.rgb.data();
        std::size_t left = frame.rgb.size();
        while (left > 0) {
            const ssize_t n = ::write(pipe_, p, left);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                sigaction(SIGPIPE, &previous, nullptr);
                return makeError(ErrorKind::Io, path_, "ffmpeg stopped taking frames");
            }
            p += n;
            left -= std::size_t(n);
        }
        sigaction(SIGPIPE, &previous, nullptr);
    }
    ++written_;
    return {};
}

Status FrameOutput::finish() {
    if (kind_ != Kind::Video || ffmpeg_ <= 0) return {};
    close(pipe_);
    pipe_ = -1;
    int status = 0;
    waitpid(ffmpeg_, &status, 0);
    ffmpeg_ = -1;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return makeError(ErrorKind::Io, path_,
                         "ffmpeg failed (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    return {};
}

} // namespace rubble::viewer
