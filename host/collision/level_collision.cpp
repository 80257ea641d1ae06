// host/collision/level_collision.cpp: a body against a static mesh's triangles (stage
// narrowPhase, CPU) over rubble/shared/level_contact.h; see level_collision.h.
#include "host/collision/level_collision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "host/core/math.h"

namespace rubble {
namespace {

// The farthest a point of the body can have moved in the level's frame since `made`, m: its
// origin's move plus the chord 2 sin(theta / 2) = ||R - R0||_F / sqrt(2) of its turn times its
// bounding radius.
float levelDrift(const shared::RigidTransform& made, const shared::RigidTransform& now,
                 float bodyRadius) {
    const shared::Mat3 r = now.rotation, q = made.rotation;
    const shared::float4 d0 = shared::sub4(r.r0, q.r0), d1 = shared::sub4(r.r1, q.r1),
                         d2 = shared::sub4(r.r2, q.r2);
    const float chord =
        std::sqrt(0.5f * (shared::dot3(d0, d0) + shared::dot3(d1, d1) + shared::dot3(d2, d2)));
    return shared::length3(shared::sub4(now.translation, made.translation)) + chord * bodyRadius;
}

// A level manifold (level frame, normal from the level to the body) kept with the body at
// `bodyInLevel`: each point's surface point on the level (level frame) and on the body (body
// frame), at depth / 2 on either side of it along the normal.
shared::RecycledManifold keptLevelManifold(const shared::ContactManifold& inLevel,
                                           const shared::RigidTransform& bodyInLevel) {
    shared::RecycledManifold r = shared::emptyRecycledManifoldItem();
    r.made = bodyInLevel;
    r.normal = inLevel.normal;
    r.count = inLevel.count;
    for (std::uint32_t i = 0; i < inLevel.count; ++i) {
        const shared::float4 p =
            shared::vec4(inLevel.points[i].x, inLevel.points[i].y, inLevel.points[i].z);
        const shared::float4 half = shared::scale4(inLevel.normal, 0.5f * inLevel.points[i].w);
        r.pointA[i] = shared::add4(p, half);
        r.pointB[i] = shared::transformApplyInverse(bodyInLevel, shared::sub4(p, half));
        r.features[i] = inLevel.features[i];
    }
    return r;
}

// A kept level manifold with the body at `bodyInLevel`, level frame: each point's separation
// along the kept normal recomputed and the point placed where the triangle test puts it; points
// beyond the margin left out.
shared::ContactManifold rebuiltLevelManifold(const shared::RecycledManifold& r,
                                             const shared::RigidTransform& bodyInLevel,
                                             float margin) {
    shared::ContactManifold m = shared::emptyContactsItem();
    const shared::float4 n = r.normal;
    m.normal = n;
    for (std::uint32_t i = 0; i < r.count; ++i) {
        const shared::float4 onLevel = r.pointA[i];
        const shared::float4 onBody = shared::transformApply(bodyInLevel, r.pointB[i]);
        const float s = shared::dot3(n, shared::sub4(onBody, onLevel));
        if (s > margin) continue;
        // What made the point (an edge pair first: its tag holds the hull edge's index too).
        const std::uint32_t tag = r.features[i] & 0x7FFFu;
        const shared::float4 half = shared::scale4(n, 0.5f * s);
        const shared::float4 position =
            (tag & RUBBLE_TRIANGLE_TAG_EDGES) ? shared::scale4(shared::add4(onLevel, onBody), 0.5f)
            : (tag & RUBBLE_TRIANGLE_TAG_ON_TRIANGLE) ? shared::add4(onLevel, half)
            : (tag & RUBBLE_TRIANGLE_TAG_ON_BODY)
                ? shared::sub4(onBody, half)
                : shared::scale4(shared::add4(onLevel, onBody), 0.5f);
        shared::addContactItem(&m, position, -s, r.features[i]);
    }
    return m;
}

} // namespace

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

void LevelCandidateCache::carry(const BodyPair& pair) {
    while (cursor_ < entries_.size() && entries_[cursor_].pair < pair) ++cursor_;
    if (cursor_ == entries_.size() || !(entries_[cursor_].pair == pair)) return;
    Entry entry = entries_[cursor_];
    const auto first = std::ptrdiff_t(entry.first);
    entry.first = std::uint32_t(nextTriangles_.size());
    nextTriangles_.insert(nextTriangles_.end(), triangles_.begin() + first,
                          triangles_.begin() + first + std::ptrdiff_t(entry.count));
    next_.push_back(entry);
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

void LevelManifoldCache::beginStep() {
    next_.clear();
    nextManifolds_.clear();
    cursor_ = 0;
    recycled_ = 0;
}

bool LevelManifoldCache::recycle(const BodyPair& pair, const shared::RigidTransform& levelAt,
                                 const shared::RigidTransform& bodyInLevel, float bodyRadius,
                                 float margin, std::vector<shared::ContactManifold>& out) {
    // Pairs come in ascending order, as last step's entries are kept: walk them alongside.
    while (cursor_ < entries_.size() && entries_[cursor_].pair < pair) ++cursor_;
    if (cursor_ == entries_.size() || !(entries_[cursor_].pair == pair)) return false;
    const Entry& kept = entries_[cursor_];
    // The manifolds of one pair were made together: the first holds their pose and age.
    const shared::RecycledManifold& made = manifolds_[kept.first];
    if (made.age >= RUBBLE_RECYCLE_MAX_AGE || margin > kept.margin + RUBBLE_RECYCLE_DISTANCE ||
        levelDrift(made.made, bodyInLevel, bodyRadius) > RUBBLE_RECYCLE_DISTANCE)
        return false;
    const std::size_t start = out.size();
    std::uint32_t points = 0;
    for (std::uint32_t k = kept.first; k < kept.first + kept.count; ++k) {
        const shared::ContactManifold m = rebuiltLevelManifold(manifolds_[k], bodyInLevel, margin);
        if (m.count == 0) continue;
        out.push_back(shared::contactsToWorldItem(m, levelAt, 0));
        points += m.count;
    }
    // Every point moved past the margin: the triangles tell what touches now.
    if (points == 0) {
        out.resize(start);
        return false;
    }
    next_.push_back(Entry{pair, std::uint32_t(nextManifolds_.size()), kept.count, kept.margin});
    for (std::uint32_t k = kept.first; k < kept.first + kept.count; ++k) {
        nextManifolds_.push_back(manifolds_[k]);
        nextManifolds_.back().age += 1u;
    }
    ++recycled_;
    return true;
}

void LevelManifoldCache::keep(const BodyPair& pair, const shared::RigidTransform& levelAt,
                              const shared::RigidTransform& bodyInLevel, float margin,
                              std::span<const shared::ContactManifold> manifolds) {
    Entry entry{pair, std::uint32_t(nextManifolds_.size()), 0, margin};
    for (const shared::ContactManifold& world : manifolds) {
        if (world.count == 0) continue;
        // Back into the level's frame, where the level's points stay put.
        shared::ContactManifold inLevel = world;
        inLevel.normal = shared::transformRotateInverse(levelAt, world.normal);
        for (std::uint32_t i = 0; i < world.count; ++i) {
            const shared::float4 p = shared::transformApplyInverse(levelAt, world.points[i]);
            inLevel.points[i] = shared::make4(p.x, p.y, p.z, world.points[i].w);
        }
        nextManifolds_.push_back(keptLevelManifold(inLevel, bodyInLevel));
        ++entry.count;
    }
    if (entry.count > 0) next_.push_back(entry);
}

void LevelManifoldCache::endStep() {
    std::swap(entries_, next_);
    std::swap(manifolds_, nextManifolds_);
}

void LevelManifoldCache::clear() {
    entries_.clear();
    next_.clear();
    manifolds_.clear();
    nextManifolds_.clear();
    cursor_ = 0;
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
    // many as it can give. The scratch array only grows: its first n hold this pair's contacts.
    const glm::mat3 rotation = toLevel * toMat3(otherAt.rotation);
    const glm::vec3 translation = toLevel * (toVec3(otherAt.translation) - levelOrigin);
    std::vector<shared::TriangleContact>& contacts = scratch.contacts;
    std::uint32_t n = 0;
    const auto collide = [&](std::uint32_t room, auto&& one) {
        for (std::uint32_t k : triangles) {
            if (contacts.size() < std::size_t(n) + room) contacts.resize(std::size_t(n) + room);
            shared::ContactBuffer buffer{contacts.data(), n, n + room};
            one(meshTriangleOf(level.triangles[k], k), &buffer);
            n = buffer.count;
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
