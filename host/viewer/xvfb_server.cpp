// host/viewer/xvfb_server.cpp: Xvfb as a child process; it reports its display number on a
// pipe (-displayfd) once it is ready for clients.
#include "host/viewer/xvfb_server.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace rubble::viewer {
namespace {

constexpr int kStartTimeoutMs = 10000;

} // namespace

std::string findOnPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    if (!path) return {};
    std::string dirs(path);
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = std::min(dirs.find(':', start), dirs.size());
        const std::string dir = dirs.substr(start, end - start);
        const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
        struct stat st {};
        if (stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
            access(candidate.c_str(), X_OK) == 0)
            return candidate;
        start = end + 1;
    }
    return {};
}

Result<XvfbServer> XvfbServer::start() {
    const std::string xvfb = findOnPath("Xvfb");
    if (xvfb.empty())
        return makeError(ErrorKind::NotSupported, "Xvfb",
                         "no display, no EGL, and Xvfb is not installed (apt-get install xvfb)");
    int fds[2];
    if (pipe(fds) != 0) return makeError(ErrorKind::Io, "pipe", std::strerror(errno));
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return makeError(ErrorKind::Io, "fork", std::strerror(errno));
    }
    if (pid == 0) {
        // The child: Xvfb writes its display number to our pipe when it is ready.
        close(fds[0]);
        const int devnull = open("/dev/null", O_RDWR);
        if (devnull >= 0) {
            dup2(devnull, STDIN_FILENO);
            dup2(devnull, STDOUT_FILENO);
            dup2(devnull, STDERR_FILENO);
        }
        const std::string fd = std::to_string(fds[1]);
        execl(xvfb.c_str(), "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1920x1080x24",
              "-nolisten", "tcp", static_cast<char*>(nullptr));
        _exit(127);
    }
    close(fds[1]);

    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    while (true) {
        const int ready = poll(&p, 1, kStartTimeoutMs);
        char buf[32];
        const ssize_t n = ready > 0 ? read(fds[0], buf, sizeof buf) : -1;
        if (n <= 0) break;
        number.append(buf, std::size_t(n));
        if (number.find('\n') != std::string::npos) break;
    }
    close(fds[0]);
    while (!number.empty() && (number.back() == '\n' || number.back() == '\r')) number.pop_back();
    if (number.empty()) {
        kill(pid, SIGTERM);
        waitpid(pid, nullptr, 0);
        return makeError(ErrorKind::Io, xvfb, "the X server did not start");
    }
    return XvfbServer(pid, ":" + number);
}

XvfbServer::~XvfbServer() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
}

} // namespace rubble::viewer
