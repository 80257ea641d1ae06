// host/io/metrics.cpp: conserved quantities and the per-run summary.
#include "host/io/metrics.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

namespace rubble {
namespace {

// The CPU's stages of a step as the metrics file names them (stages_ms; device_stages_ms from
// kDeviceStageFields, rubble/world.h), each with the field that times it; the recorder sums and
// writes them from these tables alone.
constexpr StageField<StepStats> kCpuStages[] = {
    {"apply_forces", &StepStats::applyForcesMs},
    {"integrate_velocities", &StepStats::integrateVelocitiesMs},
    {"broad_phase", &StepStats::broadPhaseMs},
    {"narrow_phase", &StepStats::narrowPhaseMs},
    {"build_contact_rows", &StepStats::buildContactRowsMs},
    {"solve", &StepStats::solveMs},
    {"integrate_positions", &StepStats::integratePositionsMs},
    {"solve_positions", &StepStats::solvePositionsMs},
    {"islands", &StepStats::islandsMs}};

template <class Stats, std::size_t N>
nlohmann::ordered_json stagesJson(const Stats& totals, const StageField<Stats> (&fields)[N]) {
    nlohmann::ordered_json j;
    for (const StageField<Stats>& f : fields) j[std::string(f.name)] = totals.*f.ms;
    return j;
}

} // namespace

Invariants measureInvariants(const World& world) {
    const WorldMetrics m = world.metrics();
    return Invariants{m.kineticEnergy, m.linearMomentum, m.angularMomentum};
}

TimeHistogram::TimeHistogram()
    : bins_(std::size_t(std::ceil(std::log(kHighest / kLowest) / std::log(kRatio))), 0u) {}

void TimeHistogram::add(double ms) {
    ++count_;
    if (!(ms >= kLowest)) {
        ++zeros_;
        return;
    }
    const auto bin = std::size_t(std::log(ms / kLowest) / std::log(kRatio));
    ++bins_[std::min(bin, bins_.size() - 1)];
}

// The time of the rank-th smallest sample (0-based): the middle of the bin that holds it.
double TimeHistogram::value(std::int64_t rank) const {
    if (rank < zeros_) return 0.0;
    std::int64_t below = zeros_;
    for (std::size_t k = 0; k < bins_.size(); ++k) {
        below += bins_[k];
        if (rank < below) return kLowest * std::pow(kRatio, double(k) + 0.5);
    }
    return kHighest;
}

double TimeHistogram::percentile(double q) const {
    if (count_ == 0) return 0.0;
    const double pos = q * double(count_ - 1);
    const auto lo = std::int64_t(pos);
    const std::int64_t hi = std::min(lo + 1, count_ - 1);
    const double low = value(lo), high = hi == lo ? low : value(hi);
    return low + (high - low) * (pos - double(lo));
}

void MetricsRecorder::start(const World& world) {
    scene_ = world.sceneName();
    bodies_ = world.bodyCount();
    first_ = last_ = measureInvariants(world);
}

void MetricsRecorder::afterStep(const World& world) {
    const StepStats& s = world.lastStep();
    stepMs_.add(s.totalMs);
    for (const StageField<StepStats>& f : kCpuStages) totals_.*f.ms += s.*f.ms;
    deviceMs_.add(s.deviceMs);
    deviceWaitMs_.add(s.deviceWaitMs);
    deviceHiddenMs_.add(s.deviceHiddenMs);
    hostMs_.add(s.hostMs);
    deviceBusyMs_ += s.deviceMs;
    deviceHiddenTotalMs_ += s.deviceHiddenMs;
    for (const DeviceStageField& f : kDeviceStageFields)
        deviceStages_.*f.ms += s.deviceStages.*f.ms;
    wallS_ += s.totalMs / 1000.0;
    largestPenetration_ = std::max(largestPenetration_, s.largestPenetration);
    lastContacts_ = s.contactCount;
    maxContacts_ = std::max(maxContacts_, s.contactCount);
    lastAsleep_ = s.asleep;
    solverResidual_ = s.solverResidual;
    last_ = measureInvariants(world);
}

double percentile(std::vector<double>& v, double q) {
    if (v.empty()) return 0.0;
    const double pos = q * double(v.size() - 1);
    const std::size_t lo = std::size_t(pos);
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    // The lo-th smallest, then the smallest of those above it: the hi-th.
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(lo), v.end());
    const double low = v[lo];
    const double high = hi == lo ? low : *std::min_element(v.begin() + std::ptrdiff_t(hi), v.end());
    return low + (high - low) * (pos - double(lo));
}

namespace {
nlohmann::json vec(glm::dvec3 v) {
    return {v.x, v.y, v.z};
}
} // namespace

nlohmann::ordered_json qualityJson(const QualityReport& q) {
    nlohmann::ordered_json j;
    j["sunk"] = q.sunk;
    j["floor_penetration"] = q.floorPenetration;
    j["mean_drift"] = q.meanDrift;
    j["kinetic_energy"] = q.kineticEnergy;
    j["max_speed"] = q.maxSpeed;
    j["moving"] = q.moving;
    return j;
}

double MetricsRecorder::medianMs() const { return stepMs_.percentile(0.5); }
double MetricsRecorder::p90Ms() const { return stepMs_.percentile(0.9); }

std::string MetricsRecorder::toJson(const World& world) const {
    nlohmann::ordered_json j;
    j["scene"] = scene_;
    j["steps"] = stepMs_.count();
    j["bodies"] = bodies_;
    j["wall_s"] = wallS_;
    j["ms_per_step"] = {{"median", medianMs()}, {"p90", p90Ms()}};
    j["stages_ms"] = stagesJson(totals_, kCpuStages);
    j["kinetic_energy"] = {{"first", first_.kineticEnergy}, {"last", last_.kineticEnergy}};
    j["linear_momentum"] = {{"first", vec(first_.linearMomentum)},
                            {"last", vec(last_.linearMomentum)}};
    j["angular_momentum"] = {{"first", vec(first_.angularMomentum)},
                             {"last", vec(last_.angularMomentum)}};
    j["largest_penetration"] = largestPenetration_;
    j["contact_count"] = {{"last", lastContacts_}, {"max", maxContacts_}};
    // Sleeping is each engine's own (islands on the CPU, body by body on the device): how many
    // bodies a run put to sleep says what its late steps cost.
    j["asleep"] = {{"last", lastAsleep_}};
    j["solver_residual"] = solverResidual_;
    if (quality_) j["quality"] = qualityJson(*quality_);
    j["backend"] = std::string(toString(world.options().backend));
    j["device"] = world.deviceName();
    if (world.options().backend == Backend::OpenCl) {
        // Medians per step of the device's part, and where its time went over the run.
        const double busy = deviceBusyMs_, hidden = deviceHiddenTotalMs_;
        j["host_ms_per_step"] = {{"median", hostMs_.percentile(0.5)},
                                 {"p90", hostMs_.percentile(0.9)}};
        j["device_ms_per_step"] = {{"median", deviceMs_.percentile(0.5)},
                                   {"p90", deviceMs_.percentile(0.9)}};
        j["device_wait_ms_per_step"] = {{"median", deviceWaitMs_.percentile(0.5)}};
        j["device_hidden_ms_per_step"] = {{"median", deviceHiddenMs_.percentile(0.5)}};
        j["device_hidden_share"] = busy > 0 ? hidden / busy : 0.0;
        j["device_stages_ms"] = stagesJson(deviceStages_, kDeviceStageFields);
        nlohmann::ordered_json kernels = nlohmann::ordered_json::array();
        for (const DeviceCommandTime& c : world.deviceProfile())
            kernels.push_back(
                {{"name", c.name}, {"ms", c.ms}, {"launches", c.launches}, {"bytes", c.bytes}});
        j["device_kernels"] = kernels;
    }
    return j.dump(2) + "\n";
}

} // namespace rubble
