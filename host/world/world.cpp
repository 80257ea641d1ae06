// host/world/world.cpp: World::step() (the pipeline of the backend, then the checks every step
// needs), queries, and forces for a host program.
#include <chrono>
#include <cstdio>
#include <new>

#include "host/core/clock.h"
#include "host/core/math.h"
#include "host/gpu/memory.h"
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
        if (!isFinite(s.bodies.poses[i].position) || !isFinite(s.bodies.poses[i].orientation) ||
            !isFinite(s.bodies.momenta[i].linear) || !isFinite(s.bodies.momenta[i].angular))
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

    if (s.device) {
        // The device checks its own state for non-finite values.
        Status stepped;
        try {
            stepped = stepDevice(s, stats);
        } catch (const std::bad_alloc&) {
            stepped = outOfMemory(s);
        }
        std::fill(s.bodies.forces.begin(), s.bodies.forces.end(), BodyForce{});
        ++s.step;
        stats.totalMs = msSince(start);
        RUBBLE_TRY(stepped);
        return checkBlowUp(s);
    }
    // A stage that could not run (a budget of host/core/limits.h, a contact set too large for a
    // dense solver, a stop request) ends the step there and stops the run.
    Status stepped;
    try {
        stepped = stepCpu(s, stats);
    } catch (const std::bad_alloc&) {
        stepped = outOfMemory(s);
    }
    RUBBLE_TRY(stepped);
    std::fill(s.bodies.forces.begin(), s.bodies.forces.end(), BodyForce{});
    ++s.step;
    stats.totalMs = msSince(start);

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
std::span<const Warning> World::warnings() const { return s_->warnings; }
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
    b.position = toVec3(s.bodies.poses.at(i).position);
    b.orientation = toQuat(s.bodies.poses[i].orientation);
    b.linearVelocity = toVec3(s.bodies.velocities[i].linear);
    b.angularVelocity = toVec3(s.bodies.velocities[i].angular);
    b.linearMomentum = toVec3(s.bodies.momenta[i].linear);
    b.angularMomentum = toVec3(s.bodies.momenta[i].angular);
    b.mass = s.bodies.masses[i].mass;
    b.inertia = toMat3(s.bodies.masses[i].inertiaBody);
    b.isStatic = s.isStatic(i);
    b.isKinematic = (s.bodies.masses[i].flags & RUBBLE_BODY_KINEMATIC) != 0;
    b.asleep = (s.bodies.masses[i].flags & RUBBLE_BODY_ASLEEP) != 0;
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
    shared::BodyForce& f = s_->bodies.forces.at(i);
    f.force = toFloat4(toVec3(f.force) + force);
    s_->bodies.masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
}

void World::addTorque(std::uint32_t i, glm::vec3 torque) {
    s_->blowUp.rebase = true; // the host puts energy in
    if (const auto c = cpuBody(*s_, i)) return s_->offload->cpu->addTorque(*c, torque);
    s_->forcesDirty = s_->device != nullptr;
    shared::BodyForce& f = s_->bodies.forces.at(i);
    f.torque = toFloat4(toVec3(f.torque) + torque);
    s_->bodies.masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
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
    const glm::vec3 r = point - toVec3(s.bodies.poses.at(i).position);
    s.bodies.momenta[i].linear = toFloat4(toVec3(s.bodies.momenta[i].linear) + impulse);
    s.bodies.momenta[i].angular = toFloat4(toVec3(s.bodies.momenta[i].angular) + glm::cross(r, impulse));
    s.bodies.velocities[i] =
        shared::velocityFromMomentumItem(s.bodies.momenta[i], s.bodies.masses[i], s.bodies.poses[i].orientation);
    s.bodies.masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
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
std::vector<DeviceBuffer> World::deviceBuffers() const {
    std::vector<DeviceBuffer> out;
    if (!s_->device) return out;
    for (gpu::BufferRecord& b : gpu::deviceBuffers(s_->device->context().context()))
        out.push_back(DeviceBuffer{std::move(b.where), b.bytes});
    return out;
}
std::uint64_t World::deviceBytesPeak() const {
    return s_->device ? gpu::deviceBytesPeak(s_->device->context().context()) : 0;
}
std::uint64_t World::deviceBodyReads() const {
    return s_->device ? s_->device->bodyReads() : 0;
}
void World::keepDeviceCommands(bool keep) {
    if (s_->device) s_->device->keepCommands(keep);
}
std::span<const DeviceCommand> World::lastDeviceCommands() const {
    if (!s_->device) return {};
    return s_->device->lastCommands();
}
Result<DeviceClockSample> World::sampleDeviceClock() const {
    if (!s_->device)
        return makeError(ErrorKind::NotSupported, "sampleDeviceClock",
                         "the cpu backend has no OpenCL device");
    return gpu::sampleClock(s_->device->context().queue());
}
std::span<const ShapeGeometry> World::shapes() const { return s_->geometry; }
const ShapeGeometry& World::shape(std::uint32_t shape) const { return s_->geometry.at(shape); }
std::uint32_t World::bodyShape(std::uint32_t body) const { return s_->bodies.shapeOf.at(body); }
bool World::isDebris(std::uint32_t body) const { return s_->debris.at(body) != 0; }
std::span<const JointDesc> World::joints() const { return s_->joints; }

bool World::onDevice(std::uint32_t body) const {
    const WorldState& s = *s_;
    if (!s.device || s.isStatic(body)) return false;
    return !s.offload || s.offload->worldToCpu.at(body) == kNotOnCpu;
}

std::vector<ContactInfo> World::contacts() const {
    std::vector<ContactInfo> out;
    // An offloaded world's host contacts are its CPU world's, under the world's body indices.
    if (s_->offload) {
        const Offload& o = *s_->offload;
        out = o.cpu->contacts();
        for (ContactInfo& c : out) {
            c.a = o.cpuToWorld[c.a];
            c.b = o.cpuToWorld[c.b];
        }
        return out;
    }
    const StepContacts& c = s_->contacts;
    for (const Manifold& m : c.manifolds)
        for (std::uint32_t k = 0; k < m.count; ++k)
            out.push_back({m.a, m.b, m.points[k].position, m.normal, m.points[k].depth});
    if (!c.manifolds.empty()) return out;
    for (const shared::ParticleContact& p : c.points)
        out.push_back({p.a, p.b, toVec3(p.point), toVec3(p.normal), p.point.w});
    return out;
}

glm::vec3 World::pendingCouplingImpulse() const {
    glm::vec3 sum(0.0f);
    if (s_->offload)
        for (const shared::BodyImpulse& j : s_->offload->pending) sum += toVec3(j.linear);
    return sum;
}

std::span<const float> World::solverResiduals() const {
    if (s_->offload) return s_->offload->cpu->solverResiduals();
    if (!s_->solver) return {};
    return s_->solver->residuals();
}

} // namespace rubble
