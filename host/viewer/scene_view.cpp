// host/viewer/scene_view.cpp: a world's state into a DrawList.
#include "host/viewer/scene_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "host/core/math.h"

namespace rubble::viewer {
namespace {

constexpr float kMinGroundHalfSize = 30.0f; // m
constexpr glm::vec4 kAabbColour{0.30f, 0.85f, 0.35f, 0.8f};
constexpr glm::vec4 kContactColour{1.0f, 0.90f, 0.10f, 1.0f};
constexpr glm::vec4 kNormalColour{0.20f, 0.85f, 1.0f, 1.0f};
constexpr glm::vec4 kJointLinkColour{0.95f, 0.95f, 0.95f, 1.0f};
constexpr glm::vec4 kHingeAxisColour{1.0f, 0.30f, 0.90f, 1.0f};

glm::vec3 hsvToRgb(float h, float s, float v) {
    const float c = v * s;
    const float hp = std::fmod(h * 6.0f, 6.0f);
    const float x = c * (1.0f - std::abs(std::fmod(hp, 2.0f) - 1.0f));
    glm::vec3 rgb;
    if (hp < 1)
        rgb = {c, x, 0};
    else if (hp < 2)
        rgb = {x, c, 0};
    else if (hp < 3)
        rgb = {0, c, x};
    else if (hp < 4)
        rgb = {0, x, c};
    else if (hp < 5)
        rgb = {x, 0, c};
    else
        rgb = {c, 0, x};
    return rgb + glm::vec3(v - c);
}

glm::vec3 position(const BodyPose& p) {
    return toVec3(p.position);
}
glm::quat orientation(const BodyPose& p) {
    return toQuat(p.orientation);
}

// The 12 edges of a box given by its corners.
void boxLines(glm::vec3 lo, glm::vec3 hi, glm::vec4 colour, DrawList& out) {
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int k = 0; k < 4; ++k) {
            glm::vec3 a = lo, b;
            a[u] = (k & 1) ? hi[u] : lo[u];
            a[v] = (k & 2) ? hi[v] : lo[v];
            b = a;
            b[axis] = hi[axis];
            out.line(a, b, colour);
        }
    }
}

} // namespace

glm::vec3 bodyColour(std::uint32_t index) {
    const float golden = 0.61803398875f;
    const float hue = std::fmod(0.08f + golden * float(index), 1.0f);
    const float value = (index % 3 == 0) ? 0.90f : (index % 3 == 1 ? 0.75f : 0.60f);
    return hsvToRgb(hue, 0.62f, value);
}

SceneView::SceneView(const World& world)
    : shapes_(world.shapes().begin(), world.shapes().end()) {
    const std::uint32_t n = world.bodyCount();
    std::vector<BodyPose> poses;
    currentPoses(world, poses);
    colours_.resize(n);
    shapeOf_.resize(n);
    isStatic_.resize(n);
    isDebris_.resize(n);
    float sizeSum = 0.0f;
    std::uint32_t sized = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        colours_[i] = bodyColour(i);
        shapeOf_[i] = world.bodyShape(i);
        isStatic_[i] = world.body(i).isStatic ? 1 : 0;
        isDebris_[i] = world.isDebris(i) ? 1 : 0;
        const ShapeGeometry& shape = shapes_[shapeOf_[i]];
        if (shape.type == ShapeType::Plane) continue;
        bounds_.addSphere(position(poses[i]), shape.boundingRadius);
        sizeSum += shape.boundingRadius;
        ++sized;
    }
    if (sized) markSize_ = 0.15f * sizeSum / float(sized);
    // The ground under the bodies belongs in the picture too (a plane-less scene frames its
    // bodies only; its reference grid is drawn all the same).
    const glm::vec3 centre = bounds_.empty() ? glm::vec3(0.0f) : bounds_.centre();
    for (std::uint32_t i = 0; i < n; ++i) {
        const ShapeGeometry& shape = shapes_[shapeOf_[i]];
        if (shape.type != ShapeType::Plane) continue;
        const glm::vec3 normal = orientation(poses[i]) * shape.normal;
        const glm::vec3 onPlane =
            position(poses[i]) + orientation(poses[i]) * (shape.normal * shape.offset);
        if (!bounds_.empty()) bounds_.add(centre - normal * glm::dot(centre - onPlane, normal));
    }
    if (bounds_.empty()) bounds_.addSphere(glm::vec3(0.0f), 1.0f);

    for (const JointDesc& j : world.joints()) {
        const BodyPose& a = poses[j.a];
        const BodyPose& b = poses[j.b];
        JointView v;
        v.a = j.a;
        v.b = j.b;
        v.anchorInA = glm::inverse(orientation(a)) * (j.anchor - position(a));
        v.anchorInB = glm::inverse(orientation(b)) * (j.anchor - position(b));
        v.axisInA =
            j.type == JointType::Hinge ? glm::inverse(orientation(a)) * j.axis : glm::vec3(0.0f);
        joints_.push_back(v);
    }
}

void SceneView::setBodyColour(std::uint32_t index, glm::vec3 colour) {
    colours_.at(index) = colour;
}

void SceneView::build(std::span<const BodyPose> poses, const World* live,
                      const Overlays& overlays, DrawList& out) const {
    out.clear();
    out.instances.resize(shapes_.size());
    const std::uint32_t n =
        std::min<std::uint32_t>(std::uint32_t(shapeOf_.size()), std::uint32_t(poses.size()));
    const bool wantContacts = overlays.colours == ColourMode::State || overlays.contacts ||
                              overlays.normals;
    const std::vector<ContactInfo> contacts =
        live && wantContacts ? live->contacts() : std::vector<ContactInfo>{};

    if (overlays.colours == ColourMode::State) {
        inContact_.assign(n, 0);
        for (const ContactInfo& c : contacts)
            if (c.a < n && c.b < n) inContact_[c.a] = inContact_[c.b] = 1;
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t shape = shapeOf_[i];
        if (shapes_[shape].type == ShapeType::Plane) continue;
        glm::vec3 colour = colours_[i];
        if (overlays.colours == ColourMode::State) {
            if (isStatic_[i])
                colour = stateColour::kStatic;
            else if (live && live->body(i).asleep)
                colour = stateColour::kAsleep;
            else if (inContact_[i])
                colour = stateColour::kContact;
            else if (isDebris_[i])
                colour = stateColour::kDebris;
            else
                colour = stateColour::kFree;
        }
        out.instances[shape].push_back({glm::vec4(toVec3(poses[i].position), 0.0f),
                                        glm::vec4(poses[i].orientation.x, poses[i].orientation.y,
                                                  poses[i].orientation.z, poses[i].orientation.w),
                                        glm::vec4(colour, 1.0f)});
    }
    addGrounds(poses.first(n), out);
    if (overlays.aabbs) addAabbs(poses.first(n), out);
    if (overlays.contacts || overlays.normals) addContacts(contacts, overlays, out);
    if (overlays.joints) addJoints(poses.first(n), out);
}

void SceneView::addGrounds(std::span<const BodyPose> poses, DrawList& out) const {
    const float halfSize =
        std::max(kMinGroundHalfSize, 2.5f * glm::length(bounds_.hi - bounds_.lo));
    const glm::vec3 centre = bounds_.centre();
    bool any = false;
    for (std::uint32_t i = 0; i < poses.size(); ++i) {
        const ShapeGeometry& shape = shapes_[shapeOf_[i]];
        if (shape.type != ShapeType::Plane) continue;
        any = true;
        const glm::vec3 normal = orientation(poses[i]) * shape.normal;
        const glm::vec3 onPlane =
            position(poses[i]) + orientation(poses[i]) * (shape.normal * shape.offset);
        out.grounds.push_back(
            {normal, centre - normal * glm::dot(centre - onPlane, normal), halfSize});
    }
    // A scene with no plane still gets a reference grid, at y = 0 or under its lowest body.
    if (!any)
        out.grounds.push_back({glm::vec3(0, 1, 0),
                               glm::vec3(centre.x, std::min(0.0f, bounds_.lo.y), centre.z),
                               halfSize});
}

void SceneView::addAabbs(std::span<const BodyPose> poses, DrawList& out) const {
    for (std::uint32_t i = 0; i < poses.size(); ++i) {
        const ShapeGeometry& shape = shapes_[shapeOf_[i]];
        if (shape.type == ShapeType::Plane) continue;
        const glm::vec3 p = position(poses[i]);
        Bounds box;
        if (shape.type == ShapeType::Sphere) {
            box.addSphere(p, shape.radius);
        } else if (shape.type == ShapeType::Capsule) {
            const glm::vec3 axis = orientation(poses[i]) * glm::vec3(0.0f, shape.halfHeight, 0.0f);
            box.addSphere(p + axis, shape.radius);
            box.addSphere(p - axis, shape.radius);
        } else {
            const glm::mat3 r = glm::mat3_cast(orientation(poses[i]));
            for (const glm::vec3& v : shape.vertices) box.add(p + r * v);
        }
        if (!box.empty()) boxLines(box.lo, box.hi, kAabbColour, out);
    }
}

void SceneView::addContacts(const std::vector<ContactInfo>& contacts, const Overlays& overlays,
                            DrawList& out) const {
    const float s = markSize_;
    for (const ContactInfo& c : contacts) {
        const glm::vec3 p = c.position;
        if (overlays.contacts)
            for (int axis = 0; axis < 3; ++axis) {
                glm::vec3 d(0.0f);
                d[axis] = s;
                out.line(p - d, p + d, kContactColour);
            }
        if (overlays.normals) out.line(p, p + 4.0f * s * c.normal, kNormalColour);
    }
}

void SceneView::addJoints(std::span<const BodyPose> poses, DrawList& out) const {
    const float s = 2.0f * markSize_;
    for (const JointView& j : joints_) {
        if (j.a >= poses.size() || j.b >= poses.size()) continue;
        const glm::vec3 pa = position(poses[j.a]), pb = position(poses[j.b]);
        const glm::quat qa = orientation(poses[j.a]), qb = orientation(poses[j.b]);
        const glm::vec3 anchorA = pa + qa * j.anchorInA;
        const glm::vec3 anchorB = pb + qb * j.anchorInB;
        out.line(pa, anchorA, kJointLinkColour);
        out.line(pb, anchorB, kJointLinkColour);
        // The frame of the joint on body a: x red, y green, z blue.
        for (int axis = 0; axis < 3; ++axis) {
            glm::vec3 e(0.0f);
            e[axis] = 1.0f;
            glm::vec4 c(0.15f, 0.15f, 0.15f, 1.0f);
            c[axis] = 1.0f;
            out.line(anchorA, anchorA + s * (qa * e), c);
        }
        if (glm::length(j.axisInA) > 0.0f) {
            const glm::vec3 axis = qa * j.axisInA;
            out.line(anchorA - 2.0f * s * axis, anchorA + 2.0f * s * axis, kHingeAxisColour);
        }
    }
}

void currentPoses(const World& world, std::vector<BodyPose>& out) {
    out.resize(world.bodyCount());
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        out[i] = BodyPose{toFloat4(b.position), toFloat4(b.orientation)};
    }
}

Overlays toOverlays(const OverlaySettings& o) {
    Overlays v;
    v.colours = o.colourByState ? ColourMode::State : ColourMode::Body;
    v.contacts = o.contacts;
    v.normals = o.normals;
    v.aabbs = o.aabbs;
    v.joints = o.joints;
    return v;
}

Camera initialCamera(const std::optional<CameraSpec>& spec, const SceneView& view, float aspect) {
    if (spec) return Camera::lookingAt(spec->eye, spec->target);
    return Camera::framing(view.bounds(), aspect);
}

std::string statusLine(std::int64_t step, double time, const World& world,
                       const std::string& backend, const std::string& device) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%s  step %lld  t %.3f s  bodies %u  contacts %u  residual %.3g  backend %s (%s)",
                  world.sceneName().c_str(), static_cast<long long>(step), time,
                  world.bodyCount(), world.lastStep().contactCount,
                  double(world.lastStep().solverResidual), backend.c_str(), device.c_str());
    return buf;
}

std::string replayLine(std::int64_t step, double time, const World& world,
                       const std::string& path) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s  step %lld  t %.3f s  bodies %u  replay of %s",
                  world.sceneName().c_str(), static_cast<long long>(step), time, world.bodyCount(),
                  path.c_str());
    return buf;
}

std::string stageLine(const StepStats& s) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "ms/step %.2f: forces %.2f  velocities %.2f  broad %.2f  narrow %.2f  rows %.2f"
                  "  solve %.2f  positions %.2f  joints %.2f  islands %.2f",
                  s.totalMs, s.applyForcesMs, s.integrateVelocitiesMs, s.broadPhaseMs,
                  s.narrowPhaseMs, s.buildContactRowsMs, s.solveMs, s.integratePositionsMs,
                  s.solvePositionsMs, s.islandsMs);
    return buf;
}

} // namespace rubble::viewer
