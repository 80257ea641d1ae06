// host/collision/level_collision.cpp: a body against a static mesh's triangles (stage
// narrowPhase, CPU) over rubble/shared/level_contact.h; see level_collision.h.
#include "host/collision/level_collision.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "host/core/math.h"

namespace rubble {

void reduceContacts(const std::vector<TriangleContact>& contacts,
                    const std::vector<std::uint32_t>& group, std::vector<std::uint32_t>& kept) {
    std::vector<shared::TriangleContact> items(contacts.size());
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        items[i].position = toFloat4(contacts[i].position);
        items[i].normal = toFloat4(contacts[i].normal);
        items[i].depth = contacts[i].depth;
        items[i].feature = contacts[i].feature;
    }
    std::uint32_t keep[RUBBLE_MAX_CONTACT_POINTS];
    const std::uint32_t n =
        shared::reduceLevelGroupItem(items.data(), group.data(), std::uint32_t(group.size()), keep);
    kept.assign(keep, keep + n);
}

BvhBox levelQueryBox(const shared::RigidTransform& levelAt, const Aabb& otherBox) {
    const glm::mat3 toLevel = glm::transpose(toMat3(levelAt.rotation));
    const glm::vec3 levelOrigin = toVec3(levelAt.translation);
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
    return query;
}

void LevelCandidateCache::beginStep() {
    next_.clear();
    nextTriangles_.clear();
    cursor_ = 0;
    reused_ = 0;
    queried_ = 0;
}

void LevelCandidateCache::candidates(const BodyPair& pair, const LevelMesh& level,
                                     const BvhBox& query, std::vector<std::uint32_t>& out) {
    // Pairs come in ascending order, as last step's entries are kept: walk them alongside.
    while (cursor_ < entries_.size() && entries_[cursor_].pair < pair) ++cursor_;
    const bool known = cursor_ < entries_.size() && entries_[cursor_].pair == pair;
    Entry entry;
    if (known && contains(entries_[cursor_].box, query)) {
        entry = entries_[cursor_];
        const auto first = std::ptrdiff_t(entry.first);
        entry.first = std::uint32_t(nextTriangles_.size());
        nextTriangles_.insert(nextTriangles_.end(), triangles_.begin() + first,
                              triangles_.begin() + first + std::ptrdiff_t(entry.count));
        ++reused_;
    } else {
        // Outside its region (or new): the hierarchy again, for the grown box.
        const glm::vec3 grow(kLevelCandidateMargin);
        entry.pair = pair;
        entry.box = BvhBox{query.min - grow, query.max + grow};
        entry.first = std::uint32_t(nextTriangles_.size());
        level.bvh.query(entry.box, nextTriangles_);
        entry.count = std::uint32_t(nextTriangles_.size()) - entry.first;
        ++queried_;
    }
    next_.push_back(entry);
    // The grown box's triangles, ascending, whose own boxes overlap the query: the hierarchy's
    // answer for the query itself, since every such triangle overlaps the grown box too.
    out.clear();
    const std::span<const BvhBox> boxes = level.bvh.triangleBoxes();
    for (std::uint32_t k = entry.first; k < entry.first + entry.count; ++k)
        if (boxesOverlap(boxes[nextTriangles_[k]], query)) out.push_back(nextTriangles_[k]);
}

const BvhBox* LevelCandidateCache::keptBox(const BodyPair& pair) const {
    const auto at = std::lower_bound(entries_.begin(), entries_.end(), pair,
                                     [](const Entry& e, const BodyPair& p) { return e.pair < p; });
    return at != entries_.end() && at->pair == pair ? &at->box : nullptr;
}

void LevelCandidateCache::endStep() {
    std::swap(entries_, next_);
    std::swap(triangles_, nextTriangles_);
}

void LevelCandidateCache::clear() {
    entries_.clear();
    next_.clear();
    triangles_.clear();
    nextTriangles_.clear();
    cursor_ = 0;
}

bool LevelCandidateCache::contains(const BvhBox& outer, const BvhBox& inner) {
    return outer.min.x <= inner.min.x && outer.min.y <= inner.min.y && outer.min.z <= inner.min.z &&
           inner.max.x <= outer.max.x && inner.max.y <= outer.max.y && inner.max.z <= outer.max.z;
}

void collideLevel(const LevelMesh& level, const shared::RigidTransform& levelAt, const Shape& other,
                  const shared::RigidTransform& otherAt, const Aabb& otherBox, float margin,
                  LevelScratch& scratch, std::vector<shared::ContactManifold>& out) {
    scratch.triangles.clear();
    level.bvh.query(levelQueryBox(levelAt, otherBox), scratch.triangles);
    collideLevelTriangles(level, levelAt, other, otherAt, scratch.triangles, margin, scratch, out);
}

void collideLevelTriangles(const LevelMesh& level, const shared::RigidTransform& levelAt,
                           const Shape& other, const shared::RigidTransform& otherAt,
                           std::span<const std::uint32_t> triangles, float margin,
                           LevelScratch& scratch, std::vector<shared::ContactManifold>& out) {
    if (triangles.empty()) return;
    const glm::mat3 levelRotation = toMat3(levelAt.rotation);
    const glm::vec3 levelOrigin = toVec3(levelAt.translation);
    const glm::mat3 toLevel = glm::transpose(levelRotation);
    // The other shape in the level's frame; each triangle's contacts appended with room for as
    // many as it can give.
    const glm::mat3 rotation = toLevel * toMat3(otherAt.rotation);
    const glm::vec3 translation = toLevel * (toVec3(otherAt.translation) - levelOrigin);
    std::vector<shared::TriangleContact>& contacts = scratch.contacts;
    contacts.clear();
    const auto collide = [&](std::uint32_t room, auto&& one) {
        for (std::uint32_t k : triangles) {
            const auto count = std::uint32_t(contacts.size());
            contacts.resize(count + room);
            shared::ContactBuffer buffer{contacts.data(), count, count + room};
            one(meshTriangleOf(level.triangles[k], k), &buffer);
            contacts.resize(buffer.count);
        }
    };
    switch (other.type) {
    case ShapeType::Sphere: {
        const float4 centre = toFloat4(translation);
        collide(1u, [&](const shared::MeshTriangle& t, shared::ContactBuffer* b) {
            shared::collideTriangleSphereItem(t, centre, other.radius, margin, b);
        });
        break;
    }
    case ShapeType::Capsule: {
        const shared::CapsuleSegment s{toFloat4(translation - rotation[1] * other.halfHeight),
                                       toFloat4(translation + rotation[1] * other.halfHeight)};
        collide(2u, [&](const shared::MeshTriangle& t, shared::ContactBuffer* b) {
            shared::collideTriangleCapsuleItem(t, s, other.radius, margin, b);
        });
        break;
    }
    case ShapeType::Box:
    case ShapeType::Convex:
    case ShapeType::Mesh: {
        if (other.halfEdge.empty()) return; // another level mesh
        placeHull(other.halfEdge, rotation, translation, scratch.hull);
        const auto room = std::uint32_t(scratch.hull.polygon.size());
        collide(room, [&](const shared::MeshTriangle& t, shared::ContactBuffer* b) {
            shared::collideTriangleHullItem(t, scratch.hull.view, margin, b);
        });
        break;
    }
    case ShapeType::Plane:
        return;
    }

    // Group by normal, in the order the triangles came, and reduce each group.
    const auto n = std::uint32_t(contacts.size());
    scratch.taken.assign(n, 0u);
    scratch.group.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        if (scratch.taken[i]) continue;
        const std::uint32_t members = shared::gatherLevelGroupItem(
            contacts.data(), n, i, 1u, scratch.taken.data(), scratch.group.data());
        std::uint32_t kept[RUBBLE_MAX_CONTACT_POINTS];
        const std::uint32_t count =
            shared::reduceLevelGroupItem(contacts.data(), scratch.group.data(), members, kept);
        shared::ContactManifold m = shared::emptyContactsItem();
        m.normal = toFloat4(levelRotation * toVec3(contacts[i].normal));
        for (std::uint32_t k = 0; k < count; ++k) {
            const glm::vec3 p = levelRotation * toVec3(contacts[kept[k]].position) + levelOrigin;
            shared::addContactItem(&m, toFloat4(p), contacts[kept[k]].depth,
                                   contacts[kept[k]].feature);
        }
        out.push_back(m);
    }
}

} // namespace rubble
