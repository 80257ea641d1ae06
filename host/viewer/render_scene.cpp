// host/viewer/render_scene.cpp: `rubble render`: frames of a simulated or recorded scene drawn
// off-screen and written as PNG files or a video.
#include <cstdio>
#include <optional>

#include "host/viewer/frame_output.h"
#include "host/viewer/offscreen_context.h"
#include "host/viewer/render_target.h"
#include "host/viewer/renderer.h"
#include "host/viewer/replay.h"
#include "host/viewer/scene_view.h"
#include "host/viewer/viewer.h"
#include "rubble/world.h"

namespace rubble::viewer {
namespace {

constexpr int kMaxSize = 8192; // px, either side

Status checkSettings(const RenderSettings& s) {
    if (s.width < 16 || s.height < 16 || s.width > kMaxSize || s.height > kMaxSize)
        return makeError(ErrorKind::BadInput, "--size",
                         "must be WxH with each side from 16 to " + std::to_string(kMaxSize));
    if (s.frames < 1) return makeError(ErrorKind::BadInput, "--frames", "must be 1 or more");
    if (s.every < 1) return makeError(ErrorKind::BadInput, "--every", "must be 1 or more");
    if (s.start < 0) return makeError(ErrorKind::BadInput, "--start", "must be 0 or more");
    if (s.fps < 1 || s.fps > 240)
        return makeError(ErrorKind::BadInput, "--fps", "must be 1 to 240");
    if (s.samples < 1 || s.samples > 16)
        return makeError(ErrorKind::BadInput, "--samples", "must be 1 to 16");
    if (s.out.empty()) return makeError(ErrorKind::BadInput, "--out", "is required");
    return {};
}

} // namespace

Status renderScene(const Scene& scene, const RunOptions& run, const RenderSettings& s) {
    RUBBLE_TRY(checkSettings(s));
    Result<World> world = World::create(scene, run);
    if (!world) return world.error();
    std::optional<Replay> replay;
    if (!s.replay.empty()) {
        Result<Replay> r = Replay::load(s.replay, *world);
        if (!r) return r.error();
        replay.emplace(std::move(*r));
    }
    Result<FrameOutput> out = FrameOutput::open(s.out, s.frames, s.width, s.height, s.fps);
    if (!out) return out.error();

    Result<OffscreenContext> context = OffscreenContext::create(s.context);
    if (!context) return context.error();
    Result<Renderer> renderer = Renderer::create(world->shapes());
    if (!renderer) return renderer.error();
    renderer->setTextScale(s.height >= 600 ? 2.0f : 1.0f);
    Result<RenderTarget> target = RenderTarget::create(s.width, s.height, s.samples);
    if (!target) return target.error();
    if (!s.quiet)
        std::fprintf(stderr, "rubble: rendering with %s\n", context->description().c_str());

    const SceneView view(*world);
    const Overlays overlays = toOverlays(s.overlays);
    const Camera camera = initialCamera(s.camera, view, float(s.width) / float(s.height));
    DrawList frame;
    std::vector<BodyPose> poses;
    std::optional<Error> failure;
    for (int i = 0; i < s.frames; ++i) {
        const std::int64_t wanted = std::int64_t(s.start) + std::int64_t(i) * s.every;
        if (replay) {
            if (wanted > replay->frames().back().step) {
                std::fprintf(stderr, "rubble: %s ends at step %lld; %d of %d frames written\n",
                             replay->path().c_str(),
                             static_cast<long long>(replay->frames().back().step), i, s.frames);
                break;
            }
            const ReplayFrame& f = replay->atStep(wanted);
            view.build(f.poses, nullptr, overlays, frame);
            if (s.overlays.stats)
                frame.text.push_back(replayLine(f.step, f.time, *world, replay->path()));
        } else {
            while (world->stepIndex() < wanted) {
                if (Status st = world->step(); !st) {
                    failure = st.error();
                    break;
                }
            }
            if (failure) break;
            currentPoses(*world, poses);
            view.build(poses, &*world, overlays, frame);
            if (s.overlays.stats) {
                const std::string backend(toString(world->options().backend));
                frame.text.push_back(statusLine(world->stepIndex(), world->time(), *world,
                                                backend, world->deviceName()));
                frame.text.push_back(stageLine(world->lastStep()));
            }
        }
        target->bind();
        renderer->draw(frame, camera, s.width, s.height);
        RUBBLE_TRY(out->write(target->read()));
    }
    RUBBLE_TRY(out->finish());
    if (failure) return *failure;
    if (out->written() == 0)
        return makeError(ErrorKind::BadInput, "--start",
                         "no frame to render: the recording ends before step " +
                             std::to_string(s.start));
    if (!s.quiet)
        std::printf("%s: %d frame%s %dx%d, wrote %s\n", world->sceneName().c_str(), out->written(),
                    out->written() == 1 ? "" : "s", s.width, s.height, out->path().c_str());
    return {};
}

} // namespace rubble::viewer
