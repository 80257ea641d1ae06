// host/io/metrics.h: the run summary of `--metrics FILE.json` (SCENE_FORMAT.md, Outputs) and the
// conserved quantities it reports.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "host/io/quality.h"
#include "rubble/error.h"
#include "rubble/world.h"

namespace rubble {

/// Totals over the dynamic bodies, world frame, about the world origin.
struct Invariants {
    double kineticEnergy = 0;         ///< J, translational plus rotational
    glm::dvec3 linearMomentum{0.0};   ///< kg m/s
    glm::dvec3 angularMomentum{0.0};  ///< kg m^2/s, sum of x cross P + L
};

/// The q-quantile (0..1) of samples, interpolated linearly between neighbours; 0 when empty.
/// O(n) (selection, not a sort); reorders `samples`.
double percentile(std::vector<double>& samples, double q);

/// Step times in fixed memory: counts in bins whose bounds grow by kRatio from kLowest ms, so
/// that a run of any length keeps the same few kilobytes and a percentile comes out within half
/// a bin (0.5 %) of the exact one. Times below kLowest (0 on a backend without a device) count
/// as 0; times above the last bin count in it.
class TimeHistogram {
  public:
    static constexpr double kLowest = 1e-6;  ///< ms
    static constexpr double kHighest = 1e7;  ///< ms
    static constexpr double kRatio = 1.01;   ///< from one bin bound to the next

    TimeHistogram();
    void add(double ms);
    std::int64_t count() const { return count_; }
    /// The q-quantile (0..1) as percentile() defines it, each of the two ranks it interpolates
    /// taken at the geometric middle of its bin; 0 when empty. O(bins).
    double percentile(double q) const;

  private:
    std::vector<std::uint32_t> bins_;
    std::int64_t zeros_ = 0, count_ = 0;
    double value(std::int64_t rank) const;
};

/// The world's kinetic energy and momenta now: those of World::metrics.
Invariants measureInvariants(const World& world);

/// Collects per-step figures while a world runs, then writes them as JSON.
class MetricsRecorder {
  public:
    /// Records the initial state; call before the first step.
    void start(const World& world);
    /// Records the step that just ran.
    void afterStep(const World& world);

    /// Median and 90th percentile of the step times so far (TimeHistogram: within 0.5 %).
    double medianMs() const;
    double p90Ms() const;
    /// Steps recorded.
    std::int64_t steps() const { return stepMs_.count(); }
    double wallSeconds() const { return wallS_; }
    std::uint32_t lastContacts() const { return lastContacts_; }

    /// Records the end-state assessment of the run (written as "quality").
    void setQuality(const QualityReport& q) { quality_ = q; }

    /// The summary as JSON text.
    std::string toJson(const World& world) const;

  private:
    std::string scene_;
    std::uint32_t bodies_ = 0;
    // Per-step times in fixed memory, so that a long run's recorder does not grow with it.
    TimeHistogram stepMs_;
    // The device's part of each step (OpenCL backend): busy, waited for, hidden; host time.
    TimeHistogram deviceMs_, deviceWaitMs_, deviceHiddenMs_, hostMs_;
    double deviceBusyMs_ = 0, deviceHiddenTotalMs_ = 0;
    DeviceStageMs deviceStages_;
    StepStats totals_;
    Invariants first_, last_;
    float largestPenetration_ = 0;
    std::uint32_t lastContacts_ = 0, maxContacts_ = 0;
    std::uint32_t lastAsleep_ = 0; ///< bodies asleep after the last step
    float solverResidual_ = 0;
    double wallS_ = 0;
    std::optional<QualityReport> quality_;
};

/// The "quality" object of a metrics file.
nlohmann::ordered_json qualityJson(const QualityReport& q);

} // namespace rubble
