// include/rubble/shared/level_contact.h: a body against a static level mesh in stage narrowPhase,
// both pipelines: the contacts of the triangles under the body's box (triangle_contact.h)
// grouped by normal and each group reduced to at most four points. The CPU
// (host/collision/level_collision.cpp) queries its hierarchy itself and keeps every group as a
// manifold; the device (kernels/sat.cl) walks the flattened hierarchy here and makes the one
// manifold its pair slot holds: the normal of the group with the deepest point, and the points
// of every group within RUBBLE_LEVEL_MERGE_COSINE of it.
#pragma once

#include "rubble/shared/triangle_hull_contact.h"

RUBBLE_SHARED_BEGIN

// Contacts whose normals have a cosine above this (about 5.7 degrees apart) share a manifold: the
// facets of a curved surface under one body give it one or two manifolds, not one each.
#define RUBBLE_SAME_NORMAL_COSINE 0.995f
// Points closer than this (m) are one when a group is reduced.
#define RUBBLE_LEVEL_SAME_POINT 1e-5f
// Contacts one triangle gives at most on the device (a hull's largest face plus three).
#define RUBBLE_LEVEL_TRIANGLE_CONTACTS                                                             \
    (RUBBLE_HULL_MAX_FACE_VERTICES + RUBBLE_TRIANGLE_EXTRA_CONTACTS)
// On the device, the contacts whose normals are within this cosine (about 26 degrees) of the
// deepest group's share its manifold.
#define RUBBLE_LEVEL_MERGE_COSINE 0.9f
// On the device, a pair collides with the triangles under its box in batches of at most this
// many (one walk of the hierarchy each), and holds at most this many contacts of them at once,
// in private memory.
#define RUBBLE_LEVEL_MAX_TRIANGLES 32u
#define RUBBLE_LEVEL_MAX_CONTACTS 64u
// On the device, hulls with at most this many vertices and faces (and twice as many edges) are
// placed in the level's frame once per pair, in private memory.
#define RUBBLE_LEVEL_PLACED_VERTICES 16u
// The deepest a level mesh's hierarchy goes on the device (host/geometry/triangle_bvh.h's
// kBvhMaxDepth); the walk's stack holds two entries per level.
#define RUBBLE_LEVEL_MAX_DEPTH 64u
// HullShape.level of a shape that is no level mesh.
#define RUBBLE_NO_LEVEL 0xFFFFFFFFu

// 48 bytes: one node of a level mesh's hierarchy (host/geometry/triangle_bvh.h's BvhNode),
// indices relative to its level's first node and triangle. A leaf holds `count` triangles from
// `first`; an inner node (count 0) has its children at `first` and `second`.
typedef struct LevelNode {
    float4 boxMin, boxMax; // mesh frame, m (w = 0)
    uint first, count, second, pad0;
} LevelNode;
RUBBLE_STATIC_ASSERT_SIZE(LevelNode, 48);

// 16 bytes: where one level mesh's nodes and triangles start (triangles in its hierarchy's leaf
// order, each naming its own index).
typedef struct LevelShape {
    uint nodeStart, nodeCount, triangleStart, triangleCount;
} LevelShape;
RUBBLE_STATIC_ASSERT_SIZE(LevelShape, 16);

// The concatenated level meshes (device buffers).
typedef struct LevelArrays {
    RUBBLE_GLOBAL const LevelShape* levels;
    RUBBLE_GLOBAL const LevelNode* nodes;
    RUBBLE_GLOBAL const MeshTriangle* triangles;
} LevelArrays;

// Lists in `group` the contacts from `leader` on not yet taken (taken 0) whose normals are within
// RUBBLE_SAME_NORMAL_COSINE of the leader's, and takes them with `mark` (not 0); returns how many.
RUBBLE_FN uint gatherLevelGroupItem(const TriangleContact* contacts, uint n, uint leader, uint mark,
                                    uint* taken, uint* group) {
    uint count = 0;
    for (uint j = leader; j < n; ++j)
        if (!taken[j] &&
            dot3(contacts[j].normal, contacts[leader].normal) >= RUBBLE_SAME_NORMAL_COSINE) {
            taken[j] = mark;
            group[count++] = j;
        }
    return count;
}

RUBBLE_FN float levelTriangleAreaItem(float4 a, float4 b, float4 c) {
    return 0.5f * length3(cross3(sub4(b, a), sub4(c, a)));
}

// Up to four of the group's points (indices into `contacts`, into kept), spanning the largest
// area: the deepest, the furthest from it, the furthest from their line, and the one that adds
// most area; returns how many. Points within RUBBLE_LEVEL_SAME_POINT of a kept one are left out.
RUBBLE_FN uint reduceLevelGroupItem(const TriangleContact* contacts, const uint* group, uint n,
                                    uint* kept) {
    if (n == 0u) return 0u;
    uint first = group[0];
    for (uint i = 0; i < n; ++i)
        if (contacts[group[i]].depth > contacts[first].depth) first = group[i];
    kept[0] = first;
    const float4 p0 = contacts[first].position;
    // The furthest from the deepest.
    uint second = first;
    float far = RUBBLE_LEVEL_SAME_POINT;
    for (uint i = 0; i < n; ++i) {
        const float d = length3(sub4(contacts[group[i]].position, p0));
        if (d > far) {
            far = d;
            second = group[i];
        }
    }
    if (second == first) return 1u;
    kept[1] = second;
    const float4 p1 = contacts[second].position;
    // The furthest from their line.
    uint third = first;
    float area = RUBBLE_LEVEL_SAME_POINT * RUBBLE_LEVEL_SAME_POINT;
    for (uint i = 0; i < n; ++i) {
        const float a = levelTriangleAreaItem(p0, p1, contacts[group[i]].position);
        if (a > area) {
            area = a;
            third = group[i];
        }
    }
    if (third == first) return 2u;
    kept[2] = third;
    const float4 p2 = contacts[third].position;
    // The one outside the triangle that adds most area.
    const float base = levelTriangleAreaItem(p0, p1, p2);
    uint fourth = first;
    float added = RUBBLE_LEVEL_SAME_POINT * RUBBLE_LEVEL_SAME_POINT;
    for (uint i = 0; i < n; ++i) {
        const float4 p = contacts[group[i]].position;
        const float a = levelTriangleAreaItem(p0, p1, p) + levelTriangleAreaItem(p1, p2, p) +
                        levelTriangleAreaItem(p2, p0, p) - base;
        if (a > added) {
            added = a;
            fourth = group[i];
        }
    }
    if (fourth == first) return 3u;
    kept[3] = fourth;
    return 4u;
}

// Whether the closed boxes overlap (host/geometry/triangle_bvh.h's boxesOverlap).
RUBBLE_FN int levelBoxesOverlapItem(float4 aMin, float4 aMax, float4 bMin, float4 bMax) {
    return aMin.x <= bMax.x && bMin.x <= aMax.x && aMin.y <= bMax.y && bMin.y <= aMax.y &&
           aMin.z <= bMax.z && bMin.z <= aMax.z;
}

// Makes room in a full contact buffer: each group of normals (as gatherLevelGroupItem forms
// them) keeps its leader and the points reduceLevelGroupItem keeps of it, in their order. The
// deepest point of each group, its leader's normal and the group's extent survive, so the
// manifold made at the end is near the one all the points would give.
RUBBLE_FN void compactLevelContactsItem(ContactBuffer* out, uint* taken, uint* group) {
    const uint n = out->count;
    for (uint i = 0; i < n; ++i) taken[i] = 0u;
    // taken: 0 unseen, else 1 + the leader; keep marks go in bit 31.
    for (uint i = 0; i < n; ++i) {
        if (taken[i]) continue;
        const uint members = gatherLevelGroupItem(out->items, n, i, i + 1u, taken, group);
        uint kept[RUBBLE_MAX_CONTACT_POINTS];
        const uint count = reduceLevelGroupItem(out->items, group, members, kept);
        taken[i] |= 0x80000000u;
        for (uint k = 0; k < count; ++k) taken[kept[k]] |= 0x80000000u;
    }
    uint w = 0;
    for (uint i = 0; i < n; ++i)
        if (taken[i] & 0x80000000u) out->items[w++] = out->items[i];
    out->count = w;
}

// The level mesh `level` at `levelAt` against `other` (a hull, sphere or capsule) at `otherAt`,
// whose world box is (boxMin, boxMax): one manifold in the world frame (the deepest group's
// normal, the points of the groups near it reduced to four), normal from the level to the other
// body (a and b left for the caller). When RUBBLE_LEVEL_MAX_CONTACTS would not hold the next
// triangle's contacts, the buffer is compacted (compactLevelContactsItem).
RUBBLE_FN ContactManifold collideLevelItem(HullArrays arrays, LevelArrays levels, uint level,
                                           RigidTransform levelAt, HullShape other,
                                           RigidTransform otherAt, float4 boxMin, float4 boxMax,
                                           float margin) {
    ContactManifold m = emptyContactsItem();
    const LevelShape shape = levels.levels[level];
    RUBBLE_GLOBAL const LevelNode* nodes = levels.nodes + shape.nodeStart;
    RUBBLE_GLOBAL const MeshTriangle* triangles = levels.triangles + shape.triangleStart;
    if (shape.nodeCount == 0u) return m;
    // The other body's world box, as a box in the level's frame.
    float4 queryMin =
        vec4(-RUBBLE_TRIANGLE_LOWEST, -RUBBLE_TRIANGLE_LOWEST, -RUBBLE_TRIANGLE_LOWEST);
    float4 queryMax = vec4(RUBBLE_TRIANGLE_LOWEST, RUBBLE_TRIANGLE_LOWEST, RUBBLE_TRIANGLE_LOWEST);
    for (uint corner = 0; corner < 8u; ++corner) {
        const float4 p =
            vec4((corner & 1u) ? boxMax.x : boxMin.x, (corner & 2u) ? boxMax.y : boxMin.y,
                 (corner & 4u) ? boxMax.z : boxMin.z);
        const float4 inLevel = transformApplyInverse(levelAt, p);
        queryMin = vec4(fmin(queryMin.x, inLevel.x), fmin(queryMin.y, inLevel.y),
                        fmin(queryMin.z, inLevel.z));
        queryMax = vec4(fmax(queryMax.x, inLevel.x), fmax(queryMax.y, inLevel.y),
                        fmax(queryMax.z, inLevel.z));
    }
    // The other shape in the level's frame.
    const RigidTransform place = transformRelative(levelAt, otherAt);
    if (other.kind != RUBBLE_SHAPE_SPHERE && other.kind != RUBBLE_SHAPE_CAPSULE &&
        other.kind != RUBBLE_SHAPE_HULL)
        return m;
    const float4 axis = vec4(place.rotation.r0.y, place.rotation.r1.y, place.rotation.r2.y);
    CapsuleSegment segment;
    segment.p0 = sub4(place.translation, scale4(axis, other.halfHeight));
    segment.p1 = add4(place.translation, scale4(axis, other.halfHeight));
    TaggedPoint polygon[RUBBLE_HULL_MAX_FACE_VERTICES + RUBBLE_TRIANGLE_EXTRA_CONTACTS + 1u];
    TaggedPoint clipped[RUBBLE_HULL_MAX_FACE_VERTICES + RUBBLE_TRIANGLE_EXTRA_CONTACTS + 1u];
    PlacedHull hull;
    hull.hull = hullOfItem(arrays, other);
    hull.place = place;
    hull.toHull = mat3Transpose(place.rotation);
    hull.centroid = transformApply(place, other.centroid);
    hull.vertices = 0;
    hull.faces = 0;
    hull.edgeOrigins = 0;
    hull.edgeDirections = 0;
    hull.polygon = polygon;
    hull.clipped = clipped;
    // A small hull (a box, a rock) placed once in private memory, as the CPU places every hull;
    // a larger one is placed point by point as the triangles read it.
    float4 placedVertices[RUBBLE_LEVEL_PLACED_VERTICES];
    float4 placedFaces[RUBBLE_LEVEL_PLACED_VERTICES];
    float4 placedOrigins[2u * RUBBLE_LEVEL_PLACED_VERTICES];
    float4 placedDirections[2u * RUBBLE_LEVEL_PLACED_VERTICES];
    if (other.kind == RUBBLE_SHAPE_HULL && hull.hull.vertexCount <= RUBBLE_LEVEL_PLACED_VERTICES &&
        hull.hull.faceCount <= RUBBLE_LEVEL_PLACED_VERTICES &&
        hull.hull.edgeCount <= 2u * RUBBLE_LEVEL_PLACED_VERTICES) {
        for (uint v = 0; v < hull.hull.vertexCount; ++v)
            placedVertices[v] = placedVertexItem(hull, v);
        hull.vertices = placedVertices;
        for (uint f = 0; f < hull.hull.faceCount; ++f) placedFaces[f] = placedFaceItem(hull, f);
        for (uint e = 0; e < hull.hull.edgeCount; ++e) {
            placedOrigins[e] = placedEdgeOriginItem(hull, e);
            placedDirections[e] = placedEdgeDirectionItem(hull, e);
        }
        hull.faces = placedFaces;
        hull.edgeOrigins = placedOrigins;
        hull.edgeDirections = placedDirections;
    }

    // The triangles under the box in ascending index, as the CPU's query gives them, in batches
    // of at most RUBBLE_LEVEL_MAX_TRIANGLES: each walk of the hierarchy keeps the lowest indices
    // past the last batch's (the slots into `triangles` sorted by the triangles' indices).
    TriangleContact contacts[RUBBLE_LEVEL_MAX_CONTACTS];
    ContactBuffer out;
    out.items = contacts;
    out.count = 0u;
    out.capacity = RUBBLE_LEVEL_MAX_CONTACTS;
    uint taken[RUBBLE_LEVEL_MAX_CONTACTS], group[RUBBLE_LEVEL_MAX_CONTACTS];
    uint found[RUBBLE_LEVEL_MAX_TRIANGLES], foundIndex[RUBBLE_LEVEL_MAX_TRIANGLES];
    uint after = 0u;
    int firstBatch = 1;
    for (;;) {
        uint foundCount = 0;
        int more = 0;
        uint stack[2u * RUBBLE_LEVEL_MAX_DEPTH];
        uint top = 0;
        stack[top++] = 0u;
        while (top > 0u) {
            const LevelNode node = nodes[stack[--top]];
            if (!levelBoxesOverlapItem(node.boxMin, node.boxMax, queryMin, queryMax)) continue;
            if (node.count == 0u) {
                if (top + 2u > 2u * RUBBLE_LEVEL_MAX_DEPTH) continue;
                stack[top++] = node.second;
                stack[top++] = node.first;
                continue;
            }
            for (uint k = node.first; k < node.first + node.count; ++k) {
                const MeshTriangle t = triangles[k];
                if (!firstBatch && t.index <= after) continue;
                const float4 lo = vec4(fmin(t.v[0].x, fmin(t.v[1].x, t.v[2].x)),
                                       fmin(t.v[0].y, fmin(t.v[1].y, t.v[2].y)),
                                       fmin(t.v[0].z, fmin(t.v[1].z, t.v[2].z)));
                const float4 hi = vec4(fmax(t.v[0].x, fmax(t.v[1].x, t.v[2].x)),
                                       fmax(t.v[0].y, fmax(t.v[1].y, t.v[2].y)),
                                       fmax(t.v[0].z, fmax(t.v[1].z, t.v[2].z)));
                if (!levelBoxesOverlapItem(lo, hi, queryMin, queryMax)) continue;
                // Insertion by index; when full, the highest index waits for the next batch.
                uint at = foundCount;
                while (at > 0u && foundIndex[at - 1u] > t.index) --at;
                if (at >= RUBBLE_LEVEL_MAX_TRIANGLES) {
                    more = 1;
                    continue;
                }
                if (foundCount == RUBBLE_LEVEL_MAX_TRIANGLES) more = 1;
                const uint last = foundCount < RUBBLE_LEVEL_MAX_TRIANGLES
                                      ? foundCount
                                      : RUBBLE_LEVEL_MAX_TRIANGLES - 1u;
                for (uint j = last; j > at; --j) {
                    found[j] = found[j - 1u];
                    foundIndex[j] = foundIndex[j - 1u];
                }
                found[at] = k;
                foundIndex[at] = t.index;
                if (foundCount < RUBBLE_LEVEL_MAX_TRIANGLES) ++foundCount;
            }
        }
        // Each triangle's contacts with the other shape, the buffer compacted when a triangle's
        // might not fit.
        for (uint i = 0; i < foundCount; ++i) {
            if (out.count + RUBBLE_LEVEL_TRIANGLE_CONTACTS > out.capacity)
                compactLevelContactsItem(&out, taken, group);
            const MeshTriangle t = triangles[found[i]];
            if (other.kind == RUBBLE_SHAPE_SPHERE)
                collideTriangleSphereItem(t, place.translation, other.radius, margin, &out);
            else if (other.kind == RUBBLE_SHAPE_CAPSULE)
                collideTriangleCapsuleItem(t, segment, other.radius, margin, &out);
            else
                collideTriangleHullItem(t, hull, margin, &out);
        }
        if (!more || foundCount == 0u) break;
        after = foundIndex[foundCount - 1u];
        firstBatch = 0;
    }
    if (out.count == 0u) return m;

    // Group by normal in the order the triangles came; the group with the deepest point gives
    // the normal.
    for (uint i = 0; i < out.count; ++i) taken[i] = 0u;
    uint bestLeader = 0u;
    float bestDepth = RUBBLE_TRIANGLE_LOWEST;
    for (uint i = 0; i < out.count; ++i) {
        if (taken[i]) continue;
        const uint n = gatherLevelGroupItem(contacts, out.count, i, i + 1u, taken, group);
        for (uint j = 0; j < n; ++j)
            if (contacts[group[j]].depth > bestDepth) {
                bestDepth = contacts[group[j]].depth;
                bestLeader = i;
            }
    }
    // One manifold holds the contacts whose normals lie within RUBBLE_LEVEL_MERGE_COSINE of the
    // deepest group's, which is its normal: a body across the facets of a curved surface keeps
    // its support on all of them, where the CPU has a manifold per group. A point of another
    // group, d deep along its own normal at cosine c to this one, is d / c deep along it (how
    // far the body moves along this normal to clear it).
    const float4 normal = contacts[bestLeader].normal;
    uint n = 0;
    for (uint i = 0; i < out.count; ++i) {
        const float along = dot3(contacts[i].normal, normal);
        if (along < RUBBLE_LEVEL_MERGE_COSINE) continue;
        if (taken[i] != bestLeader + 1u) contacts[i].depth /= along;
        group[n++] = i;
    }
    uint kept[RUBBLE_MAX_CONTACT_POINTS];
    const uint count = reduceLevelGroupItem(contacts, group, n, kept);
    m.normal = transformRotate(levelAt, normal);
    for (uint i = 0; i < count; ++i) {
        const TriangleContact c = contacts[kept[i]];
        addContactItem(&m, transformApply(levelAt, c.position), c.depth, c.feature);
    }
    return m;
}

RUBBLE_SHARED_END
