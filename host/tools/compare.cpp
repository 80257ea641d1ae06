// host/tools/compare.cpp: one scene on two configurations stepped side by side; per compared
// step the divergence of the bodies' poses and each side's energy, momentum, penetration and
// solver residual (`rubble compare` prints it, the Python package returns it).
#include <algorithm>
#include <cmath>

#include "rubble/tools.h"

namespace rubble {
namespace {

CompareSample sample(const World& w, const std::vector<BodyState>& bodies) {
    CompareSample s;
    glm::dvec3 p(0.0), l(0.0);
    for (const BodyState& b : bodies) {
        if (b.isStatic) continue;
        const glm::dvec3 v(b.linearVelocity), omega(b.angularVelocity);
        const glm::dvec3 pl(b.linearMomentum), pa(b.angularMomentum);
        s.kineticEnergy += 0.5 * double(b.mass) * glm::dot(v, v) + 0.5 * glm::dot(omega, pa);
        p += pl;
        l += glm::cross(glm::dvec3(b.position), pl) + pa;
    }
    s.linearMomentum = glm::length(p);
    s.angularMomentum = glm::length(l);
    s.residual = w.lastStep().solverResidual;
    s.contacts = w.lastStep().contactCount;
    return s;
}

std::vector<BodyState> bodiesOf(const World& w) {
    std::vector<BodyState> out(w.bodyCount());
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) out[i] = w.body(i);
    return out;
}

// Divergence of the dynamic bodies: position distance and rotation angle, max and RMS.
void divergence(const std::vector<BodyState>& a, const std::vector<BodyState>& b, CompareRow& d) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].isStatic) continue;
        const double dx = glm::length(glm::dvec3(a[i].position) - glm::dvec3(b[i].position));
        // The angle of conj(qa) qb (unit quaternions), from its vector part: accurate for small
        // angles, and exactly 0 for equal orientations.
        const glm::dquat r =
            glm::conjugate(glm::dquat(a[i].orientation)) * glm::dquat(b[i].orientation);
        const double angle =
            2.0 * std::atan2(glm::length(glm::dvec3(r.x, r.y, r.z)), std::abs(r.w));
        d.positionMax = std::max(d.positionMax, dx);
        d.angleMax = std::max(d.angleMax, angle);
        d.positionRms += dx * dx;
        d.angleRms += angle * angle;
        ++n;
    }
    if (n > 0) {
        d.positionRms = std::sqrt(d.positionRms / double(n));
        d.angleRms = std::sqrt(d.angleRms / double(n));
    }
}

// Whole steps of each side per compared step: the larger dt sets the pace, and must be a
// whole multiple of the smaller.
Result<std::pair<int, int>> stepRatio(float dtA, float dtB) {
    const double big = std::max(dtA, dtB), small = std::min(dtA, dtB);
    const double ratio = big / small;
    const long whole = std::lround(ratio);
    if (std::abs(ratio - double(whole)) > 1e-4 * ratio)
        return makeError(ErrorKind::BadInput, "--a dt / --b dt",
                         "the two time steps (" + std::to_string(dtA) + " s and " +
                             std::to_string(dtB) +
                             " s) must be equal or one a whole multiple "
                             "of the other");
    return dtA >= dtB ? std::pair<int, int>{1, int(whole)} : std::pair<int, int>{int(whole), 1};
}

} // namespace

Result<Comparison> Comparison::create(const Scene& a, const RunOptions& runA, const Scene& b,
                                      const RunOptions& runB) {
    Result<std::pair<int, int>> ratio = stepRatio(a.simulation.dt, b.simulation.dt);
    RUBBLE_TRY(ratio);
    Result<World> worldA = World::create(a, runA);
    RUBBLE_TRY(worldA);
    Result<World> worldB = World::create(b, runB);
    RUBBLE_TRY(worldB);
    Comparison c;
    c.a_ = std::make_unique<World>(std::move(*worldA));
    c.b_ = std::make_unique<World>(std::move(*worldB));
    c.substepsA_ = ratio->first;
    c.substepsB_ = ratio->second;
    c.dt_ = std::max(a.simulation.dt, b.simulation.dt);
    return c;
}

Result<CompareRow> Comparison::next() {
    CompareRow row;
    row.step = step_;
    row.time = double(step_) * dt_;
    // Both sides advance to the same time; step 0 is the scenes as loaded.
    for (auto [w, substeps, out] :
         {std::tuple{a_.get(), substepsA_, &row.a}, std::tuple{b_.get(), substepsB_, &row.b}}) {
        if (step_ == 0) continue;
        float penetration = 0.0f;
        for (int i = 0; i < substeps; ++i) {
            RUBBLE_TRY(w->step());
            penetration = std::max(penetration, w->lastStep().largestPenetration);
        }
        out->penetration = penetration;
    }
    const std::vector<BodyState> bodiesA = bodiesOf(*a_), bodiesB = bodiesOf(*b_);
    const float penA = row.a.penetration, penB = row.b.penetration;
    row.a = sample(*a_, bodiesA);
    row.b = sample(*b_, bodiesB);
    row.a.penetration = penA;
    row.b.penetration = penB;
    divergence(bodiesA, bodiesB, row);
    ++step_;
    return row;
}

} // namespace rubble
