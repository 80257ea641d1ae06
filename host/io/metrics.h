// host/io/metrics.h: the run summary of `--metrics FILE.json` (SCENE_FORMAT.md, Outputs) and the
// conserved quantities it reports.
#pragma once

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

/// The world's kinetic energy and momenta now.
Invariants measureInvariants(const World& world);

/// Collects per-step figures while a world runs, then writes them as JSON.
class MetricsRecorder {
  public:
    /// Records the initial state; call before the first step.
    void start(const World& world);
    /// Records the step that just ran.
    void afterStep(const World& world);

    /// Median and 90th percentile of the step times so far: O(steps) each, so call them once
    /// at the end, not every step.
    double medianMs() const;
    double p90Ms() const;
    /// Steps recorded.
    std::int64_t steps() const { return std::int64_t(stepMs_.size()); }
    double wallSeconds() const { return wallS_; }
    std::uint32_t lastContacts() const { return lastContacts_; }

    /// Records the end-state assessment of the run (written as "quality").
    void setQuality(const QualityReport& q) { quality_ = q; }

    /// The summary as JSON text.
    std::string toJson(const World& world) const;

  private:
    std::string scene_;
    std::uint32_t bodies_ = 0;
    std::vector<double> stepMs_;
    // The device's part of each step (OpenCL backend): busy, waited for, hidden; host time.
    std::vector<double> deviceMs_, deviceWaitMs_, deviceHiddenMs_, hostMs_;
    DeviceStageMs deviceStages_;
    StepStats totals_;
    Invariants first_, last_;
    float largestPenetration_ = 0;
    std::uint32_t lastContacts_ = 0, maxContacts_ = 0;
    float solverResidual_ = 0;
    double wallS_ = 0;
    std::optional<QualityReport> quality_;
};

/// The "quality" object of a metrics file.
nlohmann::ordered_json qualityJson(const QualityReport& q);

} // namespace rubble
