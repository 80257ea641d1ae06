// host/world/world_debris.cpp: debris for a host program: added in bulk, removed once it left a
// region, and poses read into the caller's buffer for drawing (docs/debris.md).
#include <algorithm>
#include <cstring>

#include "host/core/math.h"
#include "host/dynamics/joints.h"
#include "host/gpu/pipeline.h"
#include "host/world/device_step.h"
#include "host/world/world_build.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// BodyTransform is read from the device as BodyPose records.
static_assert(sizeof(BodyTransform) == sizeof(shared::BodyPose));
static_assert(offsetof(BodyTransform, orientation) == offsetof(shared::BodyPose, orientation));
static_assert(offsetof(glm::quat, x) == 0 && offsetof(glm::quat, w) == 3 * sizeof(float),
              "glm::quat must store x, y, z, w as the device's orientation does");

BodyTransform bodyTransformOf(const shared::BodyPose& p) {
    BodyTransform t;
    t.position = glm::vec4(p.position.x, p.position.y, p.position.z, 0.0f);
    t.orientation = toQuat(p.orientation);
    return t;
}

// After the bodies changed in number or order (body i is now newIndex[i]): the CPU stages
// derive from the bodies again and forget what they kept by index (warm starts, cached
// features, sleep), and every body is awake; on the opencl backend the device arrays are built
// again instead.
Status rebuildAfterChange(WorldState& s, std::span<const std::uint32_t> newIndex) {
    if (!s.device) {
        for (BodyMass& m : s.bodies.masses) m.flags &= ~RUBBLE_BODY_ASLEEP;
        s.solver->bodiesChanged(newIndex, s.bodies.view());
        return s.collision->rebuild(s.collisionScene(), s.bodies.view(),
                                    s.options.collision.particleSpacing);
    }
    const std::shared_ptr<gpu::Context> context = s.device->sharedContext();
    gpu::PipelineHandle old = std::move(s.device);
    RUBBLE_TRY(attachDevice(s, context, s.options));
    s.device->keepProfileOf(*old);
    // Forces added before the change still act in the next step.
    s.forcesDirty = true;
    return {};
}

} // namespace

std::optional<std::uint32_t> World::findShape(std::string_view name) const {
    for (std::uint32_t i = 0; i < s_->shapes.size(); ++i)
        if (s_->shapes[i].name == name) return i;
    return std::nullopt;
}

Result<std::uint32_t> World::addDebris(std::span<const DebrisPiece> pieces) {
    s_->blowUp.rebase = true; // the bodies change: the energy watch starts again
    WorldState& s = *s_;
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        const DebrisPiece& d = pieces[k];
        const std::string where = "addDebris: pieces[" + std::to_string(k) + "]";
        if (d.shape >= s.shapes.size())
            return makeError(ErrorKind::BadInput, where + ".shape",
                             "no shape " + std::to_string(d.shape) + " (the scene has " +
                                 std::to_string(s.shapes.size()) + ")");
        if (s.shapes[d.shape].type == ShapeType::Plane)
            return makeError(ErrorKind::BadInput, where + ".shape",
                             "a plane cannot be debris (planes are static)");
        if (s.shapes[d.shape].level && s.shapes[d.shape].halfEdge.empty())
            return makeError(ErrorKind::BadInput, where + ".shape",
                             "shape \"" + s.shapes[d.shape].name +
                                 "\" is level geometry with no volume (a height field or a flat "
                                 "mesh): it cannot be debris");
        if (s.shapes[d.shape].type == ShapeType::Capsule && s.device &&
            s.options.collisionMethod() == CollisionMethod::Particles)
            return makeError(ErrorKind::NotSupported, where + ".shape",
                             "the opencl backend collides capsules with sat only");
        if (d.material >= s.materials.size())
            return makeError(ErrorKind::BadInput, where + ".material",
                             "no material " + std::to_string(d.material));
        if (!(d.mass > 0.0f) || !std::isfinite(d.mass))
            return makeError(ErrorKind::BadInput, where + ".mass",
                             "must be > 0, got " + std::to_string(d.mass));
    }
    RUBBLE_TRY(syncHost(s));
    const std::uint32_t first = s.bodyCount();
    for (const DebrisPiece& d : pieces) {
        BodyDesc b;
        b.name = d.name;
        b.shape = d.shape;
        b.material = d.material;
        b.debris = true;
        b.mass = d.mass;
        b.position = d.position;
        b.orientation = d.orientation;
        b.linearVelocity = d.linearVelocity;
        b.angularVelocity = d.angularVelocity;
        appendBody(s, b);
    }
    if (s.offload) {
        Offload& o = *s.offload;
        o.worldToCpu.resize(s.bodyCount(), kNotOnCpu);
        o.kinematic.resize(s.bodyCount(), 0);
    }
    std::vector<std::uint32_t> sameIndex(first);
    for (std::uint32_t i = 0; i < first; ++i) sameIndex[i] = i;
    RUBBLE_TRY(rebuildAfterChange(s, sameIndex));
    return first;
}

Result<std::uint32_t> World::removeDebrisOutside(glm::vec3 lo, glm::vec3 hi) {
    s_->blowUp.rebase = true; // the bodies change: the energy watch starts again
    WorldState& s = *s_;
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z)
        return makeError(ErrorKind::BadInput, "removeDebrisOutside",
                         "the box's low corner must not be above its high corner");
    RUBBLE_TRY(syncHost(s));
    const std::uint32_t n = s.bodyCount();
    std::vector<std::uint8_t> jointed(n, 0);
    for (const JointDesc& j : s.joints) jointed[j.a] = jointed[j.b] = 1;
    // The new index of every body that stays.
    std::vector<std::uint32_t> newIndex(n, kRemovedBody);
    std::uint32_t kept = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        const glm::vec3 x = toVec3(s.bodies.poses[i].position);
        const bool outside = glm::any(glm::lessThan(x, lo)) || glm::any(glm::greaterThan(x, hi));
        if (s.debris[i] && !s.isStatic(i) && !jointed[i] && outside) continue;
        newIndex[i] = kept++;
    }
    const std::uint32_t removed = n - kept;
    if (removed == 0) return 0u;
    auto compact = [&](auto& v) {
        for (std::uint32_t i = 0; i < n; ++i)
            if (newIndex[i] != kRemovedBody && newIndex[i] != i) v[newIndex[i]] = std::move(v[i]);
        v.resize(kept);
    };
    compact(s.names);
    compact(s.bodies.poses);
    compact(s.bodies.velocities);
    compact(s.bodies.momenta);
    compact(s.bodies.forces);
    compact(s.bodies.masses);
    compact(s.bodies.shapeOf);
    compact(s.bodies.materialOf);
    compact(s.debris);
    compact(s.surfaces);
    compact(s.velocitiesBeforeSolve);
    compact(s.velocitiesAtStart);
    for (JointDesc& j : s.joints) {
        j.a = newIndex[j.a];
        j.b = newIndex[j.b];
    }
    s.joined = joinedPairs(s.joints);
    for (shared::PgsJoint& j : s.deviceJoints) {
        j.a = newIndex[j.a];
        j.b = newIndex[j.b];
    }
    if (s.offload) {
        Offload& o = *s.offload;
        for (std::uint32_t& w : o.cpuToWorld) w = newIndex[w];
        compact(o.kinematic);
        o.worldToCpu.assign(kept, kNotOnCpu);
        for (std::uint32_t c = 0; c < o.cpuToWorld.size(); ++c) o.worldToCpu[o.cpuToWorld[c]] = c;
    }
    RUBBLE_TRY(rebuildAfterChange(s, newIndex));
    return removed;
}

Status World::readTransforms(std::uint32_t first, std::span<BodyTransform> out) const {
    const WorldState& s = *s_;
    if (std::size_t(first) + out.size() > s.bodyCount())
        return makeError(ErrorKind::BadInput, "readTransforms",
                         "bodies " + std::to_string(first) + " to " +
                             std::to_string(std::size_t(first) + out.size()) +
                             " are past the last body (" + std::to_string(s.bodyCount()) + ")");
    if (!s.device || !s.hostStale) {
        for (std::size_t k = 0; k < out.size(); ++k) out[k] = bodyTransformOf(s.bodies.poses[first + k]);
        return {};
    }
    // Straight from the device into the caller's buffer (same layout).
    RUBBLE_TRY(s.device->downloadPoses(first, std::uint32_t(out.size()), out.data()));
    if (!s.offload) return {};
    // The CPU bodies' poses on the device are this step's start: take the CPU world's.
    const Offload& o = *s.offload;
    const WorldState& c = WorldAccess::state(*o.cpu);
    for (std::uint32_t i = 0; i < o.cpuToWorld.size(); ++i) {
        const std::uint32_t w = o.cpuToWorld[i];
        if (w >= first && w - first < out.size()) out[w - first] = bodyTransformOf(c.bodies.poses[i]);
    }
    return {};
}

} // namespace rubble
