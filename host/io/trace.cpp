// host/io/trace.cpp: the device's commands of every step as Chrome trace events.
#include "host/io/trace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

namespace rubble {
namespace {

constexpr int kPid = 1;
constexpr int kDeviceTid = 1; // the device's in-order queue
constexpr int kHostTid = 2;   // World::step on the host

// device - host, ns, taking the device's reading at the middle of the host's two.
double offsetNs(const DeviceClockSample& s) {
    return double(s.deviceNs) - 0.5 * (double(s.hostBeforeNs) + double(s.hostAfterNs));
}

// Microseconds, the trace's unit, to the nanosecond.
double us(double ns) { return double(std::llround(ns)) / 1000.0; }

std::string fixed(double value, int decimals) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

// A metadata event naming the process or a thread.
nlohmann::ordered_json nameEvent(const char* what, int tid, const std::string& name) {
    return {{"name", what}, {"ph", "M"}, {"pid", kPid}, {"tid", tid}, {"args", {{"name", name}}}};
}

} // namespace

Status TraceRecorder::start(World& world) {
    world.keepDeviceCommands(true);
    Result<DeviceClockSample> s = world.sampleDeviceClock();
    RUBBLE_TRY(s);
    first_ = *s;
    return {};
}

void TraceRecorder::afterStep(const World& world, Clock::time_point begin, Clock::time_point end) {
    const auto step = std::uint32_t(world.stepIndex());
    for (const DeviceCommand& c : world.lastDeviceCommands()) commands_.push_back(Command{step, c});
    steps_.push_back(HostStep{step, steadyNs(begin), steadyNs(end), world.lastStep().deviceWaitMs});
}

Status TraceRecorder::finish(const World& world) {
    Result<DeviceClockSample> s = world.sampleDeviceClock();
    RUBBLE_TRY(s);
    last_ = *s;
    finished_ = true;
    return {};
}

std::string TraceRecorder::toJson(const World& world) const {
    // The host's steps on the device's clock: host + offset, known to within half the enqueue
    // of the first sample's marker. A device without the QUEUED time (0) gives no relation.
    const bool mapped = first_.deviceNs != 0;
    const double offset = offsetNs(first_);
    const double within = 0.5 * double(first_.hostAfterNs - first_.hostBeforeNs);
    // Zero is the earliest event: the first step's start on the host, or the first command.
    double origin = commands_.empty() ? 0.0 : double(commands_.front().command.startNs);
    if (mapped && !steps_.empty())
        origin = commands_.empty() ? double(steps_.front().begin) + offset
                                   : std::min(origin, double(steps_.front().begin) + offset);

    // Each event is built and written on its own, so the text is the only large thing held.
    std::string out = "{\"traceEvents\":[";
    auto add = [&out](const nlohmann::ordered_json& event) {
        out += out.back() == '[' ? "\n" : ",\n";
        out += event.dump();
    };
    add(nameEvent("process_name", kDeviceTid, "rubble run " + world.sceneName()));
    add(nameEvent("thread_name", kDeviceTid, "device queue: " + world.deviceName()));
    if (mapped) add(nameEvent("thread_name", kHostTid, "host: World::step"));
    for (const auto& [step, c] : commands_) {
        nlohmann::ordered_json e;
        e["name"] = c.name;
        e["cat"] = c.stage;
        e["ph"] = "X";
        e["ts"] = us(double(c.startNs) - origin);
        e["dur"] = us(double(c.endNs - c.startNs));
        e["pid"] = kPid;
        e["tid"] = kDeviceTid;
        e["args"] = {{"step", step},
                     {"queued_to_start_us", us(double(c.startNs - c.queuedNs))},
                     {"submit_to_start_us", us(double(c.startNs - c.submitNs))}};
        add(e);
    }
    if (mapped)
        for (const HostStep& s : steps_) {
            nlohmann::ordered_json e;
            e["name"] = "step " + std::to_string(s.step);
            e["cat"] = "host";
            e["ph"] = "X";
            e["ts"] = us(double(s.begin) + offset - origin);
            e["dur"] = us(double(s.end - s.begin));
            e["pid"] = kPid;
            e["tid"] = kHostTid;
            e["args"] = {{"step", s.step}, {"device_wait_ms", s.waitMs}};
            add(e);
        }

    nlohmann::ordered_json other;
    other["scene"] = world.sceneName();
    other["device"] = world.deviceName();
    other["steps"] = std::to_string(steps_.size());
    other["commands"] = std::to_string(commands_.size());
    if (!mapped)
        other["clock"] = "the device gave no CL_PROFILING_COMMAND_QUEUED time: no host steps";
    else {
        std::string clock = "device clock - host steady clock: " + fixed(offset * 1e-3, 3) +
                            " us (within " + fixed(within * 1e-3, 3) + " us) before the first step";
        if (finished_)
            clock += ", " + fixed(offsetNs(last_) * 1e-3, 3) + " us (within " +
                     fixed(0.5e-3 * double(last_.hostAfterNs - last_.hostBeforeNs), 3) +
                     " us) after the last";
        other["clock"] = clock;
    }
    // The device's buffers at the end of the run, the largest first, each by the call that
    // made it, and the most they held at once (host/gpu/memory.h).
    const auto mibText = [](std::uint64_t bytes) { return fixed(double(bytes) / 1048576.0, 3); };
    std::string buffers;
    for (const DeviceBuffer& b : world.deviceBuffers())
        buffers += (buffers.empty() ? "" : ", ") + b.where + " " + mibText(b.bytes) + " MiB";
    other["device_buffers_peak"] = mibText(world.deviceBytesPeak()) + " MiB";
    other["device_buffers"] = buffers;
    out += "\n],\n\"displayTimeUnit\":\"ms\",\n\"otherData\":";
    out += other.dump();
    out += "}\n";
    return out;
}

} // namespace rubble
