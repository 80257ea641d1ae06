// host/collision/level_collision.cpp: a body against a static mesh's triangles (stage
// narrowPhase, CPU); see level_collision.h.
#include "host/collision/level_collision.h"

#include <cmath>
#include <limits>

#include "host/core/math.h"

namespace rubble {
namespace {

// Points closer than this (m) are one.
constexpr float kSamePoint = 1e-5f;

float triangleArea(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    return 0.5f * glm::length(glm::cross(b - a, c - a));
}

} // namespace

void reduceContacts(const std::vector<TriangleContact>& contacts,
                    const std::vector<std::uint32_t>& group, std::vector<std::uint32_t>& kept) {
    kept.clear();
    if (group.empty()) return;
    const auto at = [&](std::uint32_t k) { return contacts[k].position; };
    std::uint32_t first = group[0];
    for (std::uint32_t k : group)
        if (contacts[k].depth > contacts[first].depth) first = k;
    kept.push_back(first);
    // The furthest from the deepest.
    std::uint32_t second = first;
    float far = kSamePoint;
    for (std::uint32_t k : group) {
        const float d = glm::length(at(k) - at(first));
        if (d > far) far = d, second = k;
    }
    if (second == first) return;
    kept.push_back(second);
    // The furthest from their line.
    std::uint32_t third = first;
    float area = kSamePoint * kSamePoint;
    for (std::uint32_t k : group) {
        const float a = triangleArea(at(first), at(second), at(k));
        if (a > area) area = a, third = k;
    }
    if (third == first) return;
    kept.push_back(third);
    // The one outside the triangle that adds most area.
    const float base = triangleArea(at(first), at(second), at(third));
    std::uint32_t fourth = first;
    float added = kSamePoint * kSamePoint;
    for (std::uint32_t k : group) {
        const float a = triangleArea(at(first), at(second), at(k)) +
                        triangleArea(at(second), at(third), at(k)) +
                        triangleArea(at(third), at(first), at(k)) - base;
        if (a > added) added = a, fourth = k;
    }
    if (fourth != first) kept.push_back(fourth);
}

void collideLevel(const LevelMesh& level, const shared::RigidTransform& levelAt, const Shape& other,
                  const shared::RigidTransform& otherAt, const Aabb& otherBox, float margin,
                  LevelScratch& scratch, std::vector<shared::ContactManifold>& out) {
    const glm::mat3 levelRotation = toMat3(levelAt.rotation);
    const glm::vec3 levelOrigin = toVec3(levelAt.translation);
    const glm::mat3 toLevel = glm::transpose(levelRotation);
    // The other body's world box, as a box in the level's frame.
    BvhBox query{glm::vec3(std::numeric_limits<float>::max()),
                 glm::vec3(-std::numeric_limits<float>::max())};
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p(corner & 1 ? otherBox.max.x : otherBox.min.x,
                          corner & 2 ? otherBox.max.y : otherBox.min.y,
                          corner & 4 ? otherBox.max.z : otherBox.min.z);
        const glm::vec3 local = toLevel * (p - levelOrigin);
        query.min = glm::min(query.min, local);
        query.max = glm::max(query.max, local);
    }
    scratch.triangles.clear();
    level.bvh.query(query, scratch.triangles);
    if (scratch.triangles.empty()) return;

    // The other shape in the level's frame.
    const glm::mat3 rotation = toLevel * toMat3(otherAt.rotation);
    const glm::vec3 translation = toLevel * (toVec3(otherAt.translation) - levelOrigin);
    scratch.contacts.clear();
    switch (other.type) {
    case ShapeType::Sphere:
        for (std::uint32_t k : scratch.triangles)
            collideTriangleSphere(level.triangles[k], k, translation, other.radius, margin,
                                  scratch.contacts);
        break;
    case ShapeType::Capsule: {
        const Segment s{translation - rotation[1] * other.halfHeight,
                        translation + rotation[1] * other.halfHeight};
        for (std::uint32_t k : scratch.triangles)
            collideTriangleCapsule(level.triangles[k], k, s, other.radius, margin,
                                   scratch.contacts);
        break;
    }
    case ShapeType::Box:
    case ShapeType::Convex:
    case ShapeType::Mesh:
        if (other.halfEdge.empty()) return; // another level mesh
        placeHull(other.halfEdge, rotation, translation, scratch.hull);
        for (std::uint32_t k : scratch.triangles)
            collideTriangleHull(level.triangles[k], k, scratch.hull, margin, scratch.contacts);
        break;
    case ShapeType::Plane:
        return;
    }

    // Group by normal, in the order the triangles came, and reduce each group.
    std::vector<TriangleContact>& contacts = scratch.contacts;
    std::vector<std::uint8_t>& taken = scratch.taken;
    taken.assign(contacts.size(), 0);
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        if (taken[i]) continue;
        scratch.group.clear();
        for (std::size_t j = i; j < contacts.size(); ++j)
            if (!taken[j] &&
                glm::dot(contacts[j].normal, contacts[i].normal) >= kSameNormalCosine) {
                taken[j] = 1;
                scratch.group.push_back(std::uint32_t(j));
            }
        reduceContacts(contacts, scratch.group, scratch.kept);
        shared::ContactManifold m = shared::emptyContactsItem();
        m.normal = toFloat4(levelRotation * contacts[i].normal);
        for (std::uint32_t k : scratch.kept) {
            const glm::vec3 p = levelRotation * contacts[k].position + levelOrigin;
            shared::addContactItem(&m, toFloat4(p), contacts[k].depth, contacts[k].feature);
        }
        out.push_back(m);
    }
}

} // namespace rubble
