// host/viewer/replay.cpp: CSV and JSON-lines trajectories parsed back into poses.
#include "host/viewer/replay.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "host/core/math.h"

namespace rubble::viewer {
namespace {

constexpr std::string_view kCsvHeader = "step,time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";
constexpr const char* kPoseKeys[7] = {"px", "py", "pz", "qw", "qx", "qy", "qz"};
constexpr std::size_t kCsvFields = 16;

// Builds the frames as rows arrive, one step at a time.
class FrameBuilder {
  public:
    FrameBuilder(const std::string& path, const World& world)
        : path_(path), sceneName_(world.sceneName()) {
        for (std::uint32_t i = 0; i < world.bodyCount(); ++i)
            byName_.emplace(world.bodyName(i), i);
        current_.resize(world.bodyCount());
        for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
            const BodyState b = world.body(i);
            current_[i] = BodyPose{toFloat4(b.position), toFloat4(b.orientation)};
        }
    }

    Error error(std::size_t line, const std::string& message) const {
        return makeError(ErrorKind::BadInput, path_ + ":" + std::to_string(line), message);
    }

    // Starts a new frame when the step changes; steps must not go backwards.
    Status beginRow(std::size_t line, std::int64_t step, double time) {
        if (!frames_.empty() && step == frames_.back().step) return {};
        if (!frames_.empty() && step < frames_.back().step)
            return error(line, "step " + std::to_string(step) + " comes after step " +
                                   std::to_string(frames_.back().step));
        if (!frames_.empty()) frames_.back().poses = current_;
        frames_.push_back(ReplayFrame{step, time, {}});
        return {};
    }

    // pose: px, py, pz, qw, qx, qy, qz as in the file.
    Status body(std::size_t line, std::string_view name, const double (&pose)[7]) {
        const auto it = byName_.find(std::string(name));
        if (it == byName_.end())
            return error(line, "body \"" + std::string(name) + "\" is not in the scene " +
                                   sceneName_);
        for (int k = 0; k < 7; ++k)
            if (!std::isfinite(pose[k]))
                return error(line, std::string(kPoseKeys[k]) + " of body \"" + std::string(name) +
                                       "\" is not a finite number");
        const glm::quat q{static_cast<float>(pose[3]), static_cast<float>(pose[4]),
                          static_cast<float>(pose[5]), static_cast<float>(pose[6])};
        const float length = glm::length(q);
        if (!(length > 1e-6f))
            return error(line, "the orientation of body \"" + std::string(name) + "\" is zero");
        current_[it->second] =
            BodyPose{toFloat4(glm::vec3(float(pose[0]), float(pose[1]), float(pose[2]))),
                     toFloat4(q / length)};
        return {};
    }

    Result<std::vector<ReplayFrame>> finish() {
        if (frames_.empty())
            return makeError(ErrorKind::BadInput, path_, "the trajectory has no steps");
        frames_.back().poses = current_;
        return std::move(frames_);
    }

  private:
    const std::string& path_;
    std::string sceneName_;
    std::unordered_map<std::string, std::uint32_t> byName_;
    std::vector<BodyPose> current_;
    std::vector<ReplayFrame> frames_;
};

template <class T> bool parseNumber(std::string_view text, T& out) {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, out);
    return ec == std::errc() && ptr == end;
}

std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> fields;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = line.find(',', start);
        fields.push_back(
            line.substr(start, comma == std::string_view::npos ? line.npos : comma - start));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return fields;
}

Status readCsv(std::istream& in, FrameBuilder& b) {
    std::string line;
    std::size_t number = 1;
    if (!std::getline(in, line)) return b.error(1, "the file is empty");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line != kCsvHeader)
        return b.error(1, "expected the header \"" + std::string(kCsvHeader) + "\"");
    static const char* const kNames[kCsvFields] = {"step", "time", "body", "px", "py", "pz",
                                                   "qw",   "qx",   "qy",   "qz", "vx", "vy",
                                                   "vz",   "wx",   "wy",   "wz"};
    while (std::getline(in, line)) {
        ++number;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) continue;
        std::vector<std::string_view> f = split(line);
        if (f.size() < kCsvFields)
            return b.error(number, "expected " + std::to_string(kCsvFields) + " fields, got " +
                                       std::to_string(f.size()));
        // A body name with commas in it: the fields around it are fixed.
        const std::size_t extra = f.size() - kCsvFields;
        const std::string_view name(
            f[2].data(), std::size_t(f[2 + extra].data() + f[2 + extra].size() - f[2].data()));
        std::int64_t step = 0;
        double time = 0, pose[7];
        if (!parseNumber(f[0], step))
            return b.error(number, "step: not an integer: \"" + std::string(f[0]) + "\"");
        if (!parseNumber(f[1], time))
            return b.error(number, "time: not a number: \"" + std::string(f[1]) + "\"");
        for (std::size_t k = 3; k < kCsvFields; ++k) {
            double v = 0;
            if (!parseNumber(f[k + extra], v))
                return b.error(number, std::string(kNames[k]) + ": not a number: \"" +
                                           std::string(f[k + extra]) + "\"");
            if (k < 10) pose[k - 3] = v;
        }
        RUBBLE_TRY(b.beginRow(number, step, time));
        RUBBLE_TRY(b.body(number, name, pose));
    }
    return {};
}

Status readJsonLines(std::istream& in, FrameBuilder& b) {
    using nlohmann::json;
    std::string line;
    std::size_t number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (line.empty() || line == "\r") continue;
        const json j = json::parse(line, nullptr, /*allow_exceptions=*/false);
        if (j.is_discarded() || !j.is_object()) return b.error(number, "not a JSON object");
        if (!j.contains("step") || !j["step"].is_number_integer())
            return b.error(number, "step: expected an integer");
        if (!j.contains("time") || !j["time"].is_number())
            return b.error(number, "time: expected a number");
        if (!j.contains("bodies") || !j["bodies"].is_array())
            return b.error(number, "bodies: expected an array");
        RUBBLE_TRY(b.beginRow(number, j["step"].get<std::int64_t>(), j["time"].get<double>()));
        const json& bodies = j["bodies"];
        for (std::size_t i = 0; i < bodies.size(); ++i) {
            const json& body = bodies[i];
            const std::string at = "bodies[" + std::to_string(i) + "]";
            if (!body.is_object() || !body.contains("body") || !body["body"].is_string())
                return b.error(number, at + ".body: expected a string");
            double pose[7];
            for (int k = 0; k < 7; ++k) {
                if (!body.contains(kPoseKeys[k]) || !body[kPoseKeys[k]].is_number())
                    return b.error(number, at + "." + kPoseKeys[k] + ": expected a number");
                pose[k] = body[kPoseKeys[k]].get<double>();
            }
            RUBBLE_TRY(b.body(number, body["body"].get<std::string>(), pose));
        }
    }
    return {};
}

} // namespace

Result<Replay> Replay::load(const std::string& path, const World& world) {
    const bool csv = path.size() > 4 && path.ends_with(".csv");
    const bool jsonl = path.size() > 6 && path.ends_with(".jsonl");
    if (!csv && !jsonl)
        return makeError(ErrorKind::BadInput, "--replay " + path,
                         "the trajectory file must end in .csv or .jsonl");
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(ErrorKind::BadInput, path, "cannot open the trajectory file");
    FrameBuilder builder(path, world);
    RUBBLE_TRY(csv ? readCsv(in, builder) : readJsonLines(in, builder));
    Result<std::vector<ReplayFrame>> frames = builder.finish();
    if (!frames) return frames.error();
    Replay r;
    r.path_ = path;
    r.frames_ = std::move(*frames);
    return r;
}

const ReplayFrame& Replay::atStep(std::int64_t step) const {
    // Frames are sorted by step: the last one not after `step`.
    const auto it =
        std::upper_bound(frames_.begin(), frames_.end(), step,
                         [](std::int64_t s, const ReplayFrame& f) { return s < f.step; });
    return it == frames_.begin() ? frames_.front() : *(it - 1);
}

} // namespace rubble::viewer
