// host/app/run_command.cpp: `rubble run SCENE`: step a scene, write its trajectory and metrics.
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <optional>

#include "host/app/commands.h"
#include "host/core/math.h"
#include "host/io/metrics.h"
#include "host/io/trace.h"
#include "host/io/trajectory_writer.h"
#include "rubble/world.h"

namespace rubble::app {
namespace {

// SIGINT and SIGTERM stop the run between two stages of a step (RunOptions::stop): the output
// keeps every step completed. A second signal of the same kind ends the process at once.
std::atomic<bool> gStop{false};
volatile std::sig_atomic_t gSignal = 0;
extern "C" void onStopSignal(int signal) {
    if (gSignal == signal) {
        std::signal(signal, SIG_DFL);
        std::raise(signal);
        return;
    }
    gSignal = signal;
    gStop.store(true);
}

// A one-line progress bar on stderr, redrawn at most ten times a second.
// The rate shown is the mean of the steps since the last redraw, so that drawing costs O(1).
class Progress {
  public:
    Progress(bool enabled, int total) : enabled_(enabled && total > 0), total_(total) {}
    void update(int done, double stepMs) {
        if (!enabled_) return;
        sumMs_ += stepMs;
        ++steps_;
        const auto now = Clock::now();
        if (done < total_ && now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        const double msPerStep = sumMs_ / double(steps_);
        sumMs_ = 0.0;
        steps_ = 0;
        const int width = 30;
        const int filled = int(double(width) * done / total_);
        std::fprintf(stderr, "\r[%.*s%*s] %3d%% %d/%d steps, %.2f ms/step", filled,
                     "##############################", width - filled, "", 100 * done / total_,
                     done, total_, msPerStep);
        std::fflush(stderr);
    }
    void clear() {
        if (enabled_) std::fprintf(stderr, "\r\033[K");
    }

  private:
    using Clock = std::chrono::steady_clock;
    bool enabled_;
    int total_;
    Clock::time_point last_{};
    double sumMs_ = 0.0;
    int steps_ = 0;
};

// The exit status of a run stopped by a signal: 128 + its number, as a shell reports it.
int stoppedStatus() { return gSignal == SIGTERM ? kExitTerminated : kExitInterrupted; }

// The bodies as the end-state assessment sees them.
std::vector<QualityBody> qualityBodies(const World& w) {
    std::vector<QualityBody> out(w.bodyCount());
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
        const BodyState b = w.body(i);
        out[i].shape = &w.shape(w.bodyShape(i));
        out[i].mass = b.mass;
        out[i].inertia = glm::dmat3(b.inertia);
        out[i].isStatic = b.isStatic;
    }
    return out;
}

void snapshot(const World& w, std::vector<TrajectoryRow>& rows) {
    rows.resize(w.bodyCount());
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
        const BodyState b = w.body(i);
        rows[i] = TrajectoryRow{w.bodyName(i), b.position, b.orientation, b.linearVelocity,
                                b.angularVelocity};
    }
}

} // namespace

int runCommand(const RunArgs& args) {
    Result<Scene> scene = loadScene(args.scene);
    if (!scene) return report(scene.error());
    if (Status s = applyOverrides(args.overrides, *scene); !s) return report(s.error());
    if (args.every < 1) return report(makeError(ErrorKind::BadInput, "--every", "must be 1 or more"));
    // A trace is the device's commands: the cpu backend has none to give.
    if (!args.trace.empty() && scene->simulation.backend != Backend::OpenCl)
        return report(makeError(ErrorKind::BadInput, "--trace",
                                "records the OpenCL device's commands, and this run's backend "
                                "is cpu (add --backend opencl)"));
    RunOptions run = args.run;
    run.stop = &gStop;
    Result<World> world = World::create(*scene, run);
    if (!world) return report(world.error());
    reportWarnings(*world);

    // Every output is created before the first step: a missing or read-only folder fails now,
    // not after the run (the metrics and trace files first: dropped unwritten, they leave
    // nothing).
    std::optional<AtomicFile> metricsFile;
    if (!args.metrics.empty()) {
        Result<AtomicFile> m = AtomicFile::create(args.metrics);
        if (!m) return report(m.error());
        metricsFile.emplace(std::move(*m));
    }
    std::optional<AtomicFile> traceFile;
    std::optional<TraceRecorder> trace;
    if (!args.trace.empty()) {
        Result<AtomicFile> t = AtomicFile::create(args.trace);
        if (!t) return report(makeError(t.error().kind, "--trace", t.error().describe()));
        traceFile.emplace(std::move(*t));
        trace.emplace();
        if (Status s = trace->start(*world); !s) return report(s.error());
    }
    std::optional<TrajectoryWriter> out;
    if (!args.out.empty()) {
        Result<TrajectoryWriter> w = TrajectoryWriter::open(args.out);
        if (!w) return report(w.error());
        out.emplace(std::move(*w));
        if (Status s = out->write(*world); !s) return report(s.error());
    }

    MetricsRecorder metrics;
    metrics.start(*world);
    gStop = false;
    gSignal = 0;
    std::signal(SIGINT, onStopSignal);
    std::signal(SIGTERM, onStopSignal);
    Progress progress(!args.quiet && isatty(STDERR_FILENO), scene->simulation.steps);
    std::optional<Error> failure;
    // The drift of the end-state assessment is measured over the last second of the run.
    const int steps = scene->simulation.steps;
    const int driftFrom = std::max(0, steps - int(std::lround(1.0 / scene->simulation.dt)));
    std::vector<TrajectoryRow> before, now;
    if (driftFrom == 0) snapshot(*world, before);
    for (int step = 1; step <= steps; ++step) {
        if (gStop) break;
        const Clock::time_point stepBegin = Clock::now();
        if (Status s = world->step(); !s) {
            if (s.error().kind != ErrorKind::Interrupted) failure = s.error();
            break;
        }
        if (trace) trace->afterStep(*world, stepBegin, Clock::now());
        metrics.afterStep(*world);
        if (step == driftFrom) snapshot(*world, before);
        if (out && step % args.every == 0)
            if (Status s = out->write(*world); !s) {
                progress.clear();
                return report(s.error());
            }
        progress.update(step, world->lastStep().totalMs);
    }
    progress.clear();
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);

    if (gStop && !failure) {
        std::fprintf(stderr, "rubble: %s after step %lld; the partial output is %s\n",
                     gSignal == SIGTERM ? "terminated" : "interrupted",
                     static_cast<long long>(metrics.steps()),
                     out ? out->partialPath().c_str() : "(none)");
        return stoppedStatus();
    }
    // A run that blew up keeps every step it wrote, under the final name, and says so.
    if (out)
        if (Status s = out->finish(); !s) return report(s.error());
    if (metricsFile) {
        snapshot(*world, now);
        const double interval = double(world->stepIndex() - driftFrom) * scene->simulation.dt;
        metrics.setQuality(assessQuality(qualityBodies(*world), now, before, interval));
        if (Status s = metricsFile->commit(metrics.toJson(*world)); !s) return report(s.error());
    }
    // A run that blew up keeps the trace of the steps it completed, without the clocks'
    // second sample.
    if (traceFile) {
        if (!failure)
            if (Status s = trace->finish(*world); !s) return report(s.error());
        if (Status s = traceFile->commit(trace->toJson(*world)); !s) return report(s.error());
    }
    if (failure) {
        const int code = report(*failure);
        std::fprintf(stderr, "rubble: stopped at step %lld; %s holds the steps before it\n",
                     static_cast<long long>(metrics.steps() + 1),
                     out ? out->path().c_str() : "no trajectory file");
        return code;
    }
    std::printf("%s: %lld steps, %u bodies, %u contacts, %.3f ms/step (median), %.2f s%s%s\n",
                world->sceneName().c_str(), static_cast<long long>(world->stepIndex()),
                world->bodyCount(), metrics.lastContacts(), metrics.medianMs(),
                metrics.wallSeconds(), out ? ", wrote " : "", out ? out->path().c_str() : "");
    return kExitOk;
}

} // namespace rubble::app
