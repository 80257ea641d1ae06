// kernels/sat.cl: entry point of the SAT narrow phase on the device (collideShapes): one
// manifold per pair, with the per-pair feature cache kept between steps. The math is in
// rubble/shared/narrow_phase.h (a port of host/collision's narrow phase); the CPU twin is
// SatCollision::narrowPhase (host/collision/sat_collision.cpp).
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/group.h"
#include "rubble/shared/level_contact.h"
#include "rubble/shared/narrow_phase.h"

// Work-items stride through the pairs (their count is on the device). Each writes its pair's
// manifold (count 0: no contact), cache and index among last step's entries, its pairs and the
// still pairs it carried (previousOf: their count when the pair is new; the rows' kernels read
// it instead of searching again) at the pair's index; the group adds its points to the status
// block's contact count and largest depth.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
collideShapes(const uint capacity, __global const uint* pairCount,
              __global const BodyPairRecord* pairs, const uint previousCapacity,
              __global const uint* previousCount, __global const BodyPairRecord* previousPairs,
              __global const PairCache* previousFeatures, __global const HullShape* shapes,
              __global const uint* shapeOf, __global const BodyPose* poses,
              __global const BodyVelocity* velocities, __global const uint* flags,
              __global const float* spin,
              __global const float4* vertices, __global const uint* vertexEdges,
              __global const uint* neighbourStart, __global const uint* neighbours,
              __global const HullHalfEdge* halfEdges, __global const float4* faces,
              __global const uint* faceEdges, __global const HullEdge* edges,
              __global const uint* levelOf, __global const LevelShape* levels,
              __global const LevelNode* levelNodes, __global const MeshTriangle* levelTriangles,
              __global const BodyBox* boxes, const float dt,
              __global PairCache* features, __global ContactManifold* manifolds,
              __global uint* previousOf, __global uint* status) {
    HullArrays arrays;
    arrays.vertices = vertices;
    arrays.vertexEdges = vertexEdges;
    arrays.neighbourStart = neighbourStart;
    arrays.neighbours = neighbours;
    arrays.halfEdges = halfEdges;
    arrays.faces = faces;
    arrays.faceEdges = faceEdges;
    arrays.edges = edges;
    LevelArrays levelArrays;
    levelArrays.levels = levels;
    levelArrays.nodes = levelNodes;
    levelArrays.triangles = levelTriangles;
    // The group's contact points and deepest point (float bits, depths >= 0).
    __local uint group[2];
    groupClear(group, 2u);
    const uint n = min(pairCount[0], capacity);
    // Last step's pairs, then the still pairs it carried (markStillPairs): two sorted runs.
    const uint ownRun = min(previousCount[0], previousCapacity);
    const uint previous = keptPairsItem(previousCount, previousCapacity);
    const ItemRange r = itemRange(n);
    // The work-item's pairs come in (a, b) order: last step's index of each is at or past where
    // the one before it was in its run, usually the next one.
    uint from = 0u, fromCarried = ownRun;
    for (uint p = r.first; p < r.end; p += r.step) {
        const BodyPairRecord pair = pairs[p];
        // Last step's cache of the pair; none when the pair is new.
        uint q = findPairFromItem(pair, from, ownRun, previousPairs);
        if (q < ownRun) {
            from = q + 1u;
        } else {
            q = findPairFromItem(pair, fromCarried, previous, previousPairs);
            if (q < previous) fromCarried = q + 1u;
        }
        previousOf[p] = q;
        // Features only from last step's own pairs, those it collided: a still pair carried
        // while its bodies slept runs the whole SAT when it is found again, as on the CPU, whose
        // narrow phase keeps the features of the pairs it collided only (with features from
        // before the sleep, a pile at rest at odd angles would wake to other manifolds than the
        // CPU's).
        PairCache cache = q < ownRun ? previousFeatures[q] : emptyPairCacheItem();
        // A moving kinematic body meets static and other kinematic bodies: nothing moves them.
        const uint fixed = RUBBLE_BODY_STATIC | RUBBLE_BODY_KINEMATIC;
        if ((flags[pair.a] & fixed) && (flags[pair.b] & fixed)) {
            ContactManifold none = emptyContactsItem();
            none.a = pair.a;
            none.b = pair.b;
            features[p] = cache;
            manifolds[p] = none;
            continue;
        }
        const float margin =
            pairMarginItem(velocities[pair.a], velocities[pair.b], spin[pair.a], spin[pair.b], dt);
        // A static level mesh collides by its triangles: the group of contacts with the
        // deepest point, normal from the level to the other body, turned to run from a to b.
        const uint levelA = (flags[pair.a] & RUBBLE_BODY_STATIC) ? levelOf[shapeOf[pair.a]]
                                                                : RUBBLE_NO_LEVEL;
        const uint levelB = (flags[pair.b] & RUBBLE_BODY_STATIC) ? levelOf[shapeOf[pair.b]]
                                                                : RUBBLE_NO_LEVEL;
        ContactManifold m;
        if (levelA != RUBBLE_NO_LEVEL || levelB != RUBBLE_NO_LEVEL) {
            const uint mesh = levelA != RUBBLE_NO_LEVEL ? pair.a : pair.b;
            const uint body = levelA != RUBBLE_NO_LEVEL ? pair.b : pair.a;
            const BodyBox box = boxes[body];
            m = collideLevelItem(arrays, levelArrays, levelA != RUBBLE_NO_LEVEL ? levelA : levelB,
                                 transformOfPose(poses[mesh]), shapes[shapeOf[body]],
                                 transformOfPose(poses[body]), box.min, box.max, margin);
            if (levelA == RUBBLE_NO_LEVEL) m.normal = negate4(m.normal);
        } else {
            m = collideShapesItem(arrays, shapes[shapeOf[pair.a]], transformOfPose(poses[pair.a]),
                                  shapes[shapeOf[pair.b]], transformOfPose(poses[pair.b]), &cache,
                                  margin);
        }
        m.a = pair.a;
        m.b = pair.b;
        features[p] = cache;
        manifolds[p] = m;
        if (m.count == 0u) continue;
        float deepest = 0.0f;
        for (uint k = 0; k < m.count; ++k) deepest = fmax(deepest, m.points[k].w);
        atomic_add(&group[0], m.count);
        if (deepest > 0.0f) atomic_max(&group[1], as_uint(deepest));
    }
    if (!groupDone()) return;
    if (group[0] > 0u) atomic_add(&status[RUBBLE_STATUS_CONTACTS], group[0]);
    if (group[1] > 0u) atomic_max(&status[RUBBLE_STATUS_PENETRATION], group[1]);
}
