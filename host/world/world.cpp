// host/world/world.cpp: World::step() (the pipeline of the backend, then the checks every step
// needs), queries, and forces for a host program.
#include <chrono>
#include <cstdio>
#include <new>

#include "host/core/math.h"
#include "host/gpu/pipeline.h"
#include "host/world/blowup_check.h"
#include "host/world/cpu_step.h"
#include "host/world/device_step.h"
#include "host/world/step_stop.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// The first body whose state is not finite, if any.
std::optional<std::uint32_t> firstNonFinite(const WorldState& s) {
    for (std::uint32_t i = 0; i < s.bodyCount(); ++i) {
        if (!isFinite(s.poses[i].position) || !isFinite(s.poses[i].orientation) ||
            !isFinite(s.momenta[i].linear) || !isFinite(s.momenta[i].angular))
            return i;
    }
    return std::nullopt;
}

} // namespace

World::World(std::unique_ptr<WorldState> s) : s_(std::move(s)) {}
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

Status World::step() {
    WorldState& s = *s_;
    // Stages write their outputs (contact count, solver residual) into s.stats during the step.
    StepStats& stats = s.stats;
    stats = StepStats{};
    const auto start = std::chrono::steady_clock::now();

    s.stepFailure.reset();
    if (s.device) {
        // The device checks its own state for non-finite values.
        Status stepped;
        try {
            stepped = stepDevice(s, stats);
        } catch (const std::bad_alloc&) {
            stepped = outOfMemory(s);
        }
        std::fill(s.forces.begin(), s.forces.end(), BodyForce{});
        ++s.step;
        stats.totalMs = std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - start).count();
        RUBBLE_TRY(stepped);
        return checkBlowUp(s);
    }
    try {
        stepCpuReference(s, stats);
    } catch (const std::bad_alloc&) {
        s.stepFailure = outOfMemory(s);
    }
    // A stage that could not run (a contact set too large for a dense solver) stops the run.
    if (s.stepFailure) return *s.stepFailure;
    std::fill(s.forces.begin(), s.forces.end(), BodyForce{});
    ++s.step;
    stats.totalMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    if (const auto bad = firstNonFinite(s))
        return makeError(ErrorKind::Numerical, "body " + s.names[*bad],
                         "its state is not finite after step " + std::to_string(s.step) +
                             " (t = " + std::to_string(s.time()) + " s)");
    return checkBlowUp(s);
}

std::int64_t World::stepIndex() const { return s_->step; }
double World::time() const { return s_->time(); }
const SimulationOptions& World::options() const { return s_->options; }
const std::string& World::sceneName() const { return s_->sceneName; }
std::uint32_t World::bodyCount() const { return s_->bodyCount(); }
const std::string& World::bodyName(std::uint32_t body) const { return s_->names.at(body); }

std::optional<std::uint32_t> World::findBody(std::string_view name) const {
    for (std::uint32_t i = 0; i < s_->bodyCount(); ++i)
        if (s_->names[i] == name) return i;
    return std::nullopt;
}

BodyState World::body(std::uint32_t i) const {
    WorldState& s = *s_;
    // The device stepped: read every body back once, for this and the following queries.
    if (const Status synced = syncHost(s); !synced)
        std::fprintf(stderr, "rubble: reading bodies from the device: %s\n",
                     synced.error().describe().c_str());
    BodyState b;
    b.position = toVec3(s.poses.at(i).position);
    b.orientation = toQuat(s.poses[i].orientation);
    b.linearVelocity = toVec3(s.velocities[i].linear);
    b.angularVelocity = toVec3(s.velocities[i].angular);
    b.linearMomentum = toVec3(s.momenta[i].linear);
    b.angularMomentum = toVec3(s.momenta[i].angular);
    b.mass = s.masses[i].mass;
    b.isStatic = s.isStatic(i);
    b.asleep = (s.masses[i].flags & RUBBLE_BODY_ASLEEP) != 0;
    return b;
}

namespace {

// The CPU world's index of a body that an offloaded world steps on the CPU, if it is one.
std::optional<std::uint32_t> cpuBody(const WorldState& s, std::uint32_t i) {
    if (!s.offload || s.offload->worldToCpu.at(i) == kNotOnCpu) return std::nullopt;
    return s.offload->worldToCpu[i];
}

} // namespace

void World::addForce(std::uint32_t i, glm::vec3 force) {
    s_->blowUp.rebase = true; // the host puts energy in
    if (const auto c = cpuBody(*s_, i)) return s_->offload->cpu->addForce(*c, force);
    // The device wakes a sleeping body that has a force (kernels/integrate.cl).
    s_->forcesDirty = s_->device != nullptr;
    shared::BodyForce& f = s_->forces.at(i);
    f.force = toFloat4(toVec3(f.force) + force);
    s_->masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
}

void World::addTorque(std::uint32_t i, glm::vec3 torque) {
    s_->blowUp.rebase = true; // the host puts energy in
    if (const auto c = cpuBody(*s_, i)) return s_->offload->cpu->addTorque(*c, torque);
    s_->forcesDirty = s_->device != nullptr;
    shared::BodyForce& f = s_->forces.at(i);
    f.torque = toFloat4(toVec3(f.torque) + torque);
    s_->masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
}

void World::addForceAtPoint(std::uint32_t i, glm::vec3 force, glm::vec3 point) {
    addForce(i, force);
    addTorque(i, glm::cross(point - body(i).position, force));
}

void World::applyImpulse(std::uint32_t i, glm::vec3 impulse, glm::vec3 point) {
    s_->blowUp.rebase = true; // the host puts energy in
    WorldState& s = *s_;
    if (s.isStatic(i)) return;
    if (const auto c = cpuBody(s, i)) {
        s.offload->cpu->applyImpulse(*c, impulse, point);
        s.hostStale = true; // the world's copy of the CPU bodies is refreshed when read
        return;
    }
    if (const Status synced = beginHostChange(s); !synced)
        std::fprintf(stderr, "rubble: reading bodies from the device: %s\n",
                     synced.error().describe().c_str());
    const glm::vec3 r = point - toVec3(s.poses.at(i).position);
    s.momenta[i].linear = toFloat4(toVec3(s.momenta[i].linear) + impulse);
    s.momenta[i].angular = toFloat4(toVec3(s.momenta[i].angular) + glm::cross(r, impulse));
    s.velocities[i] =
        shared::velocityFromMomentumItem(s.momenta[i], s.masses[i], s.poses[i].orientation);
    s.masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
}

const StepStats& World::lastStep() const { return s_->stats; }
std::string World::deviceName() const {
    return s_->device ? s_->device->context().describe() : "cpu";
}
std::vector<DeviceCommandTime> World::deviceProfile() const {
    std::vector<DeviceCommandTime> out;
    if (!s_->device) return out;
    for (const gpu::CommandTotals& c : s_->device->profileTotals())
        out.push_back(DeviceCommandTime{std::string(c.name), c.ms, c.launches, c.bytes});
    return out;
}
WorldState& World::state() { return *s_; }
const WorldState& World::state() const { return *s_; }

} // namespace rubble
