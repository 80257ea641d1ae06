// host/scene/ragdoll.cpp: the ragdoll generator's parts and joints.
#include "host/scene/ragdoll.h"

namespace rubble {
namespace {

// One part at scale 1: a box (half extents, m), its centre relative to the chest's centre (m)
// and its mass (kg). Proportions after adult segment tables: the chest carries the pelvis, the
// forearm the hand. The head is a box too: a sphere on the neck's ball joint, touching the
// ground at one point, could spin about the line through that point and the neck for ever
// (a point contact has no spinning friction).
struct Part {
    const char* name;
    glm::vec3 halfExtents;
    glm::vec3 centre;
    float mass;
};

// Chest 0.6 m tall; head to 0.56 m above the chest's centre, feet 1.24 m below it.
constexpr Part kParts[] = {
    {"chest", {0.17f, 0.30f, 0.10f}, {0.0f, 0.0f, 0.0f}, 30.0f},
    {"head", {0.09f, 0.11f, 0.10f}, {0.0f, 0.45f, 0.0f}, 5.0f},
    {"upper_arm_l", {0.15f, 0.05f, 0.05f}, {0.34f, 0.22f, 0.0f}, 2.5f},
    {"upper_arm_r", {0.15f, 0.05f, 0.05f}, {-0.34f, 0.22f, 0.0f}, 2.5f},
    {"forearm_l", {0.19f, 0.04f, 0.04f}, {0.70f, 0.22f, 0.0f}, 2.0f},
    {"forearm_r", {0.19f, 0.04f, 0.04f}, {-0.70f, 0.22f, 0.0f}, 2.0f},
    {"thigh_l", {0.075f, 0.225f, 0.075f}, {0.09f, -0.545f, 0.0f}, 8.0f},
    {"thigh_r", {0.075f, 0.225f, 0.075f}, {-0.09f, -0.545f, 0.0f}, 8.0f},
    {"shin_l", {0.06f, 0.225f, 0.06f}, {0.09f, -1.015f, 0.0f}, 5.0f},
    {"shin_r", {0.06f, 0.225f, 0.06f}, {-0.09f, -1.015f, 0.0f}, 5.0f},
};

// A joint at scale 1: the parts it joins (indices into kParts), the anchor relative to the
// chest's centre (m), and the hinge axis.
struct Link {
    int a, b;
    JointType type;
    glm::vec3 anchor;
    glm::vec3 axis;
};

constexpr Link kLinks[] = {
    {0, 1, JointType::Ball, {0.0f, 0.32f, 0.0f}, {1.0f, 0.0f, 0.0f}},     // neck
    {0, 2, JointType::Ball, {0.18f, 0.22f, 0.0f}, {1.0f, 0.0f, 0.0f}},    // left shoulder
    {0, 3, JointType::Ball, {-0.18f, 0.22f, 0.0f}, {1.0f, 0.0f, 0.0f}},   // right shoulder
    {2, 4, JointType::Hinge, {0.50f, 0.22f, 0.0f}, {0.0f, 1.0f, 0.0f}},   // left elbow
    {3, 5, JointType::Hinge, {-0.50f, 0.22f, 0.0f}, {0.0f, 1.0f, 0.0f}},  // right elbow
    {0, 6, JointType::Ball, {0.09f, -0.31f, 0.0f}, {1.0f, 0.0f, 0.0f}},   // left hip
    {0, 7, JointType::Ball, {-0.09f, -0.31f, 0.0f}, {1.0f, 0.0f, 0.0f}},  // right hip
    {6, 8, JointType::Hinge, {0.09f, -0.78f, 0.0f}, {1.0f, 0.0f, 0.0f}},  // left knee
    {7, 9, JointType::Hinge, {-0.09f, -0.78f, 0.0f}, {1.0f, 0.0f, 0.0f}}, // right knee
};

} // namespace

RagdollParts buildRagdoll(const RagdollSpec& spec) {
    RagdollParts parts;
    const float s = spec.scale;
    for (const Part& p : kParts) {
        const std::string name = spec.prefix + "_" + p.name;
        ShapeDesc shape;
        shape.name = name;
        shape.where = spec.where + " (" + name + ")";
        shape.type = ShapeType::Box;
        shape.halfExtents = p.halfExtents * s;
        BodyDesc body;
        body.name = name;
        body.where = shape.where;
        body.shape = std::uint32_t(parts.shapes.size());
        body.material = spec.material;
        body.debris = spec.debris;
        body.mass = p.mass * s * s * s;
        body.position = spec.position + p.centre * s;
        parts.shapes.push_back(std::move(shape));
        parts.bodies.push_back(std::move(body));
    }
    for (const Link& l : kLinks) {
        JointDesc j;
        j.type = l.type;
        j.where = spec.where + " (" + parts.bodies[std::size_t(l.b)].name + " joint)";
        j.a = std::uint32_t(l.a);
        j.b = std::uint32_t(l.b);
        j.anchor = spec.position + l.anchor * s;
        j.axis = l.axis;
        parts.joints.push_back(j);
    }
    return parts;
}

} // namespace rubble
