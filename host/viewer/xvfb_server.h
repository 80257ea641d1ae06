// host/viewer/xvfb_server.h: a private X server (Xvfb) started for off-screen rendering on a
// machine with no display and no EGL, stopped when this object goes away.
#pragma once

#include <sys/types.h>

#include <string>

#include "rubble/error.h"

namespace rubble::viewer {

/// A running Xvfb child process. Move-only; the destructor stops the server.
class XvfbServer {
  public:
    /// Starts `Xvfb` from PATH on the first free display number and waits until it accepts
    /// clients. Errors: NotSupported when Xvfb is not installed, Io when it does not start.
    static Result<XvfbServer> start();

    XvfbServer(XvfbServer&& o) noexcept : pid_(o.pid_), display_(std::move(o.display_)) {
        o.pid_ = -1;
    }
    XvfbServer& operator=(XvfbServer&&) = delete;
    XvfbServer(const XvfbServer&) = delete;
    ~XvfbServer();

    /// The display name, `:N`.
    const std::string& display() const { return display_; }

  private:
    XvfbServer(pid_t pid, std::string display) : pid_(pid), display_(std::move(display)) {}
    pid_t pid_ = -1;
    std::string display_;
};

/// The full path of an executable found on PATH, or empty.
std::string findOnPath(const std::string& program);

} // namespace rubble::viewer
