// kernels/pgs_rows.cl: entry points that build the device's projected Gauss-Seidel rows: each
// pair's summary word for the host's coloring (summarizePairs), then the rows of each pair's
// manifold (buildPgsRows). The math is in rubble/shared/pgs_row.h; the CPU twin builds its rows
// in host/dynamics/contact_rows.cpp.
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/group.h"
#include "rubble/shared/narrow_phase.h"
#include "rubble/shared/pgs_coloring.h"
#include "rubble/shared/pgs_joint.h"

// One work-item per pair (striding), after the narrow phase: the pair's summary word for the
// coloring (its point count and which bodies move; 0 when it gets no rows), and what it keeps
// for the next step's warm start when it gets no rows: a pair whose bodies both stand still
// keeps last step's impulses as they were (an island woken later starts from them), a pair
// without points none. A point deep enough to push marks its pair's moving bodies for the split
// position pass, and the status block, so that the host knows before it enqueues the pass; a
// point that will have a bounce speed (pointBounceItem, as its row will) marks the status block
// for the restitution pass. A pair that keeps impulses (its points' keys, or last step's) takes
// that many PgsImpulse slots of `kept` from the status block's count (impulseStart); past the
// set's room (`impulseRoom`) it keeps none, and the host, seeing the count, grows the room and
// runs the round again.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
summarizePairs(const uint capacity, __global const uint* pairCount,
               __global const BodyPairRecord* pairs, __global const ContactManifold* manifolds,
               __global const JacobiBody* bodies, __global const BodyPose* poses,
               __global const BodyVelocity* velocities, __global const BodyVelocity* approach,
               __global const float4* surfaces, const float baumgarte, const float slop,
               const float dt, const uint warmStart, const uint previousCapacity,
               __global const uint* previousCount, __global const uint* previousOf,
               __global const uint* previousImpulseCount,
               __global const uint* previousImpulseStart,
               __global const PgsImpulse* previousImpulses, __global uint* pairRows,
               __global uint* impulseCount, __global uint* impulseStart, const uint impulseRoom,
               __global PgsImpulse* kept, __global uint* pushed, __global uint* status) {
    const uint n = min(pairCount[0], capacity);
    // Last step's entries: its pairs and the still pairs it carried (markStillPairs).
    const uint previous = warmStart ? keptPairsItem(previousCount, previousCapacity) : 0u;
    const ItemRange r = itemRange(n);
    for (uint p = r.first; p < r.end; p += r.step) {
        const uint count = manifolds[p].count;
        const BodyPairRecord pair = pairs[p];
        const uint movesA = jointInverseMassItem(bodies[pair.a]) > 0.0f;
        const uint movesB = jointInverseMassItem(bodies[pair.b]) > 0.0f;
        if (count > 0u && (movesA || movesB)) {
            pairRows[p] = count | (movesA ? RUBBLE_PGS_MOVES_A : 0u) |
                          (movesB ? RUBBLE_PGS_MOVES_B : 0u);
            // buildPgsRows and the last sweep write the slots; a room too small is run again.
            impulseStart[p] = atomic_add(&status[RUBBLE_STATUS_IMPULSES], count);
            impulseCount[p] = count;
            int pushes = 0;
            for (uint k = 0; k < count; ++k)
                pushes |=
                    pgsNormalTargetItem(manifolds[p].points[k].w, baumgarte, slop, dt).push > 0.0f;
            if (pushes) {
                if (movesA) pushed[pair.a] = 1u;
                if (movesB) pushed[pair.b] = 1u;
                status[RUBBLE_STATUS_PUSHED] = 1u;
            }
            // A pair of moving bodies this far apart in mass: the layer pass runs (layerPgs
            // leaves out jointed bodies).
            const float ia = jointInverseMassItem(bodies[pair.a]);
            const float ib = jointInverseMassItem(bodies[pair.b]);
            if (heavyOverItem(ia, ib) || heavyOverItem(ib, ia)) status[RUBBLE_STATUS_LAYERS] = 1u;
            const float restitution = fmax(surfaces[pair.a].y, surfaces[pair.b].y);
            if (restitution > 0.0f) {
                const float4 xA = poses[pair.a].position, xB = poses[pair.b].position;
                const BodyVelocity va = velocities[pair.a], vb = velocities[pair.b];
                const BodyVelocity aa = approach[pair.a], ab = approach[pair.b];
                const float4 normal = manifolds[p].normal;
                int bounces = 0;
                for (uint k = 0; k < count; ++k) {
                    const float4 point = manifolds[p].points[k];
                    const Bounce b =
                        pointBounceItem(pgsArmItem(point, xA), pgsArmItem(point, xB), normal,
                                        point.w, va, vb, aa, ab, restitution, dt);
                    bounces |= b.speed > 0.0f;
                }
                if (bounces) status[RUBBLE_STATUS_BOUNCES] = 1u;
            }
            continue;
        }
        pairRows[p] = 0u;
        uint keep = 0u, start = 0u;
        if (count > 0u) {
            const uint q = previousOf[p];
            keep = q < previous ? min(previousImpulseCount[q], 4u) : 0u;
            if (keep > 0u) start = atomic_add(&status[RUBBLE_STATUS_IMPULSES], keep);
            if (start + keep > impulseRoom) keep = 0u;
            const uint from = keep > 0u ? previousImpulseStart[q] : 0u;
            for (uint k = 0; k < keep; ++k) kept[start + k] = previousImpulses[from + k];
        }
        impulseStart[p] = start;
        impulseCount[p] = keep;
    }
}


// One work-item per pair with rows, in pair order (`order`: the index of its element): the
// rows of the pair's manifold points where its element places them (PgsElement: point k's normal
// row, friction rows and impulses at normal[k]), warm-started from last step's impulses of the
// same pair (warmStartMatchItem), and the points' keys for the next step (their impulses are
// filled in by the last sweep).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
buildPgsRows(const uint count, __global const uint* order, __global const PgsElement* elements,
             __global const ContactManifold* manifolds, __global const BodyPose* poses,
             __global const BodyVelocity* velocities, __global const BodyVelocity* approach,
             __global const JacobiBody* bodies, __global const float4* surfaces,
             const float baumgarte, const float slop,
             const float dt, const uint warmStart, const uint previousCapacity,
             __global const uint* previousCount, __global const uint* previousOf,
             __global const uint* previousImpulseCount,
             __global const uint* previousImpulseStart,
             __global const PgsImpulse* previousImpulses, __global PgsNormalRow* normalRows,
             __global PgsFrictionRows* frictionRows, __global float4* impulses,
             __global const uint* impulseStart, __global PgsImpulse* kept) {
    const uint i = get_global_id(0);
    // A device plan's order runs over every pair, those without rows marked.
    if (i >= count || order[i] == RUBBLE_PGS_NO_ELEMENT) return;
    const PgsElement e = elements[order[i]];
    const uint p = e.id, a = e.a, b = e.b;
    const uint points = e.rows & RUBBLE_PGS_POINTS;
    const uint previous = warmStart ? keptPairsItem(previousCount, previousCapacity) : 0u;
    const uint q = previousOf[p];
    const uint oldCount = q < previous ? min(previousImpulseCount[q], 4u) : 0u;
    const ContactManifold m = manifolds[p];
    const JacobiBody ja = bodies[a], jb = bodies[b];
    const float ima = jointInverseMassItem(ja), imb = jointInverseMassItem(jb);
    const float4 sa = surfaces[a], sb = surfaces[b];
    const float friction = sqrt(sa.x * sb.x);
    const float restitution = fmax(sa.y, sb.y);
    const BodyPose pa = poses[a], pb = poses[b];
    const BodyVelocity va = velocities[a], vb = velocities[b];
    const BodyVelocity aa = approach[a], ab = approach[b];
    const float4 fixedTangent = perpendicularItem(m.normal);
    const uint keptAt = impulseStart[p];
    // The keys first: they choose which old point each new one takes its impulses from.
    PgsImpulse keys[4], old[4];
    for (uint k = 0; k < points; ++k) {
        const float4 point = m.points[k];
        const float4 rA = sub4(vec4(point.x, point.y, point.z),
                               vec4(pa.position.x, pa.position.y, pa.position.z));
        keys[k].pointInA = quatRotateInverse(pa.orientation, rA);
        keys[k].feature = m.features[k];
    }
    const uint from = oldCount > 0u ? previousImpulseStart[q] : 0u;
    for (uint o = 0; o < oldCount; ++o) old[o] = previousImpulses[from + o];
    const WarmStartMatch match = warmStartMatchItem(keys, points, old, oldCount);
    for (uint k = 0; k < points; ++k) {
        const float4 point = m.points[k];
        const PgsContactRow row = pgsContactRowItem(
            point, point.w, m.normal, pa.position, pb.position, va, vb, aa, ab, ima, imb,
            ja.inverseInertiaWorld, jb.inverseInertiaWorld, friction, restitution, baumgarte,
            slop, dt, fixedTangent);
        float4 start = make4(0.0f, 0.0f, 0.0f, 0.0f);
        if (match.from[k] >= 0) {
            const PgsImpulse from = old[match.from[k]];
            start.x = from.normal;
            start.y = dot3(from.friction, row.friction.tangent[0]);
            start.z = dot3(from.friction, row.friction.tangent[1]);
        }
        normalRows[e.normal[k]] = row.normal;
        frictionRows[e.normal[k]] = row.friction;
        impulses[e.normal[k]] = start;
        // What the next step starts from if no sweep runs; the last sweep overwrites it.
        PgsImpulse key = keys[k];
        key.normal = start.x;
        key.friction = add4(scale4(row.friction.tangent[0], start.y),
                            scale4(row.friction.tangent[1], start.z));
        key.pad0 = key.pad1 = 0u;
        kept[keptAt + k] = key;
    }
}
