// host/world/world_queries.cpp: what a host program (the Python package) reads from a world in
// bulk (poses and velocities into its own arrays, contacts, metrics) and what it changes at run
// time (a body's velocity, an explosion).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "host/core/math.h"
#include "host/world/device_step.h"
#include "host/world/world_build.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// The host's copy of the bodies, read back from the device first when it stepped since.
const WorldState& current(WorldState& s) {
    if (const Status synced = syncHost(s); !synced)
        std::fprintf(stderr, "rubble: reading bodies from the device: %s\n",
                     synced.error().describe().c_str());
    return s;
}

// Checks that `out` holds whole records of `width` floats for bodies first onwards.
Status checkRange(const char* call, const WorldState& s, std::uint32_t first,
                  std::size_t floats, std::size_t width) {
    if (floats % width != 0)
        return makeError(ErrorKind::BadInput, call,
                         "the output holds " + std::to_string(floats) +
                             " floats, not a multiple of " + std::to_string(width));
    const std::size_t count = floats / width;
    if (std::size_t(first) + count > s.bodyCount())
        return makeError(ErrorKind::BadInput, call,
                         "bodies " + std::to_string(first) + " to " +
                             std::to_string(std::size_t(first) + count) +
                             " are past the last body (" + std::to_string(s.bodyCount()) + ")");
    return {};
}

// Copies three components of a float4 field of each body's record into `out`.
template <class Record, class Field>
Status readVec3(const char* call, WorldState& s, std::uint32_t first, std::span<float> out,
                const std::vector<Record>& records, Field field) {
    RUBBLE_TRY(checkRange(call, s, first, out.size(), 3));
    RUBBLE_TRY(syncHost(s));
    for (std::size_t k = 0; k < out.size() / 3; ++k) {
        const float4 v = records[first + k].*field;
        out[3 * k] = v.x;
        out[3 * k + 1] = v.y;
        out[3 * k + 2] = v.z;
    }
    return {};
}

// The largest float not after t, so that an event at that time is due at the step starting t.
float notAfter(double t) {
    float f = float(t);
    if (double(f) > t) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}

} // namespace

Status World::readPositions(std::uint32_t first, std::span<float> out) const {
    return readVec3("readPositions", *s_, first, out, s_->bodies.poses, &BodyPose::position);
}

Status World::readOrientations(std::uint32_t first, std::span<float> out) const {
    WorldState& s = *s_;
    RUBBLE_TRY(checkRange("readOrientations", s, first, out.size(), 4));
    RUBBLE_TRY(syncHost(s));
    // The files' order, w first; the records keep x, y, z, w.
    for (std::size_t k = 0; k < out.size() / 4; ++k) {
        const float4 q = s.bodies.poses[first + k].orientation;
        out[4 * k] = q.w;
        out[4 * k + 1] = q.x;
        out[4 * k + 2] = q.y;
        out[4 * k + 3] = q.z;
    }
    return {};
}

Status World::readLinearVelocities(std::uint32_t first, std::span<float> out) const {
    return readVec3("readLinearVelocities", *s_, first, out, s_->bodies.velocities,
                    &BodyVelocity::linear);
}

Status World::readAngularVelocities(std::uint32_t first, std::span<float> out) const {
    return readVec3("readAngularVelocities", *s_, first, out, s_->bodies.velocities,
                    &BodyVelocity::angular);
}

Status World::setVelocity(std::uint32_t i, glm::vec3 linear, glm::vec3 angular) {
    WorldState& s = *s_;
    const std::string where = "setVelocity: body " + std::to_string(i);
    if (i >= s.bodyCount())
        return makeError(ErrorKind::BadInput, where,
                         "past the last body (" + std::to_string(s.bodyCount()) + ")");
    const bool kinematic = (s.bodies.masses[i].flags & RUBBLE_BODY_KINEMATIC) != 0;
    if (s.isStatic(i) && !kinematic)
        return makeError(ErrorKind::BadInput, where, s.names[i] + " is static");
    if (!isFinite(linear) || !isFinite(angular))
        return makeError(ErrorKind::BadInput, where, "the velocity must be finite");
    if (kinematic) {
        // On the device the next step sets the velocity there (noteKinematicVelocity).
        RUBBLE_TRY(syncHost(s));
        s.blowUp.rebase = true;
        s.bodies.velocities[i] = BodyVelocity{toFloat4(linear), toFloat4(angular)};
        noteKinematicVelocity(s, i);
        return {};
    }
    s.blowUp.rebase = true; // the host sets the energy: the blow-up watch starts again
    // A CPU body of an offloaded scene lives in the CPU world.
    if (s.offload && s.offload->worldToCpu.at(i) != kNotOnCpu) {
        RUBBLE_TRY(s.offload->cpu->setVelocity(s.offload->worldToCpu[i], linear, angular));
        s.hostStale = true;
        return {};
    }
    RUBBLE_TRY(beginHostChange(s));
    // The momenta are the state; the velocities are derived from them, as after a step.
    const BodyMass& m = s.bodies.masses[i];
    const BodyPose& pose = s.bodies.poses[i];
    s.bodies.momenta[i] = momentumFromVelocity(m, pose, linear, angular);
    s.bodies.velocities[i] =
        shared::velocityFromMomentumItem(s.bodies.momenta[i], m, pose.orientation);
    s.bodies.masses[i].flags &= ~RUBBLE_BODY_ASLEEP;
    return {};
}

Status World::setKinematicTarget(std::uint32_t i, glm::vec3 position, glm::quat orientation) {
    WorldState& s = *s_;
    const std::string where = "setKinematicTarget: body " + std::to_string(i);
    if (i >= s.bodyCount())
        return makeError(ErrorKind::BadInput, where,
                         "past the last body (" + std::to_string(s.bodyCount()) + ")");
    if (!(s.bodies.masses[i].flags & RUBBLE_BODY_KINEMATIC))
        return makeError(ErrorKind::BadInput, where, s.names[i] + " is not kinematic");
    const float length = glm::length(orientation);
    if (!isFinite(position) || !std::isfinite(length) || !(length > 1e-6f))
        return makeError(ErrorKind::BadInput, where,
                         "the position must be finite and the orientation a finite, non-zero "
                         "quaternion");
    // The host's copy of the pose is made current; on the device the next step sets the velocity
    // there and places the pose at its end, without an upload of the bodies.
    RUBBLE_TRY(syncHost(s));
    s.blowUp.rebase = true;
    const float dt = s.options.dt;
    const BodyPose& pose = s.bodies.poses[i];
    const glm::quat from = toQuat(pose.orientation);
    glm::quat to = orientation / length;
    // The shorter way round: q and -q are one orientation.
    if (glm::dot(from, to) < 0.0f) to = -to;
    // The turn from `from` to `to` as a rotation vector, in the world frame.
    const glm::quat turn = to * glm::conjugate(from);
    const glm::vec3 axis(turn.x, turn.y, turn.z);
    const float sine = glm::length(axis);
    const glm::vec3 rotation =
        sine > 0.0f ? axis * (2.0f * std::atan2(sine, turn.w) / sine) : glm::vec3(0.0f);
    s.bodies.velocities[i] =
        BodyVelocity{toFloat4((position - toVec3(pose.position)) / dt), toFloat4(rotation / dt)};
    noteKinematicVelocity(s, i);
    // A second target before the step replaces the first.
    const BodyPose target{toFloat4(position), toFloat4(to)};
    const auto same = std::find_if(s.kinematicTargets.begin(), s.kinematicTargets.end(),
                                   [&](const auto& t) { return t.first == i; });
    if (same != s.kinematicTargets.end())
        same->second = target;
    else
        s.kinematicTargets.push_back({i, target});
    return {};
}

std::optional<std::uint32_t> World::findMaterial(std::string_view name) const {
    for (std::uint32_t i = 0; i < s_->materials.size(); ++i)
        if (s_->materials[i].name == name) return i;
    return std::nullopt;
}

Status World::explode(glm::vec3 centre, float impulse, float radius) {
    WorldState& s = *s_;
    if (!isFinite(centre))
        return makeError(ErrorKind::BadInput, "explode: centre", "must be finite");
    if (!(impulse >= 0.0f) || !std::isfinite(impulse))
        return makeError(ErrorKind::BadInput, "explode: impulse",
                         "must be a finite number of N s, 0 or more, got " +
                             std::to_string(impulse));
    if (!(radius > 0.0f) || !std::isfinite(radius))
        return makeError(ErrorKind::BadInput, "explode: radius",
                         "must be a finite length in m greater than 0, got " +
                             std::to_string(radius));
    // An event due now: the next step's first stage applies it, on the CPU or on the device.
    EventDesc e;
    e.where = "explode";
    e.time = notAfter(s.time());
    e.centre = centre;
    e.impulse = impulse;
    e.radius = radius;
    s.events.push_back(e);
    s.eventFired.push_back(0);
    // The CPU world of an offloaded scene applies its own events to its bodies.
    if (s.offload) RUBBLE_TRY(s.offload->cpu->explode(centre, impulse, radius));
    return {};
}

WorldMetrics World::metrics() const {
    const WorldState& s = current(*s_);
    WorldMetrics r;
    r.time = s.time();
    r.step = s.step;
    r.bodies = s.bodyCount();
    const glm::dvec3 g(s.options.gravity);
    glm::dvec3 weighted(0.0);
    double mass = 0.0;
    bool first = true;
    for (std::uint32_t i = 0; i < s.bodyCount(); ++i) {
        if (s.isStatic(i)) continue;
        const BodyMass& m = s.bodies.masses[i];
        const glm::dvec3 x(toVec3(s.bodies.poses[i].position));
        const glm::dvec3 v(toVec3(s.bodies.velocities[i].linear)), w(toVec3(s.bodies.velocities[i].angular));
        const glm::dvec3 p(toVec3(s.bodies.momenta[i].linear)), l(toVec3(s.bodies.momenta[i].angular));
        ++r.dynamicBodies;
        if (m.flags & RUBBLE_BODY_ASLEEP) ++r.asleepBodies;
        r.kineticEnergy += 0.5 * glm::dot(v, p) + 0.5 * glm::dot(w, l);
        r.potentialEnergy -= double(m.mass) * glm::dot(g, x);
        r.linearMomentum += p;
        r.angularMomentum += glm::cross(x, p) + l;
        r.maxSpeed = std::max(r.maxSpeed, glm::length(v));
        weighted += double(m.mass) * x;
        mass += double(m.mass);
        const glm::vec3 xf = toVec3(s.bodies.poses[i].position);
        r.lo = first ? xf : glm::min(r.lo, xf);
        r.hi = first ? xf : glm::max(r.hi, xf);
        first = false;
    }
    if (mass > 0.0) r.centreOfMass = weighted / mass;
    r.contacts = s.stats.contactCount;
    r.largestPenetration = s.stats.largestPenetration;
    r.solverResidual = s.stats.solverResidual;
    r.stepMs = s.stats.totalMs;
    return r;
}

} // namespace rubble
