// kernels/pgs_push.cl: entry points of the split position pass of projected Gauss-Seidel on
// the device: the bounce targets (markBounces), the pass's own sweeps (pushPgs), the layer pass
// (layerPgs) and the pushes applied after integratePositions (applyPushes). The CPU twin is
// PgsSolver::solvePositions (host/dynamics/pgs_solver.cpp).
#include "rubble/shared/pgs_element.h"

// When a row may bounce (the non-fused path: the push sweeps run after the velocity sweeps), one
// work-item per element after the velocity sweeps: each row that bounces (pgsBouncesItem, from
// its accumulated normal impulse) aims the split pass at pgsPushTargetItem, written over its
// push speed, and when that is above zero marks its moving bodies as pushed and the status block
// (so that applyPushes moves them), as solvePushes marks its rows' bodies.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
markBounces(const uint count, __global const PgsElement* elements,
            __global PgsNormalRow* normalRows, __global const float4* impulses,
            __global uint* pushed, __global uint* status) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    const PgsElement e = elements[i];
    if (e.id & RUBBLE_PGS_JOINT_ELEMENT) return;
    int lifts = 0;
    for (uint k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k) {
        const PgsNormalRow r = normalRows[e.normal[k]];
        const float impulse = impulses[e.normal[k]].x;
        if (!pgsBouncesItem(r, impulse)) continue;
        const float target = pgsPushTargetItem(r, impulse);
        normalRows[e.normal[k]].speeds.y = target;
        lifts |= target > 0.0f;
    }
    if (!lifts) return;
    if (e.rows & RUBBLE_PGS_MOVES_A) atomic_or(&pushed[e.a], 1u);
    if (e.rows & RUBBLE_PGS_MOVES_B) atomic_or(&pushed[e.b], 1u);
    atomic_or(&status[RUBBLE_STATUS_PUSHED], 1u);
}

// One sweep of the split position pass alone, one launch (a color, the serial tail or the
// blocks): the non-fused path, after the velocity sweeps (and markBounces). A sweep after one
// whose largest change was within RUBBLE_PUSH_TOLERANCE does nothing.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
pushPgs(const uint first, const uint count, const uint mode,
        __global const PgsElement* elements, __global const uint* blockStarts,
        __global const PgsNormalRow* normalRows,
        __global float4* impulses, __global const uint* pushed, __global BodyVelocity* push,
        const float relaxation, const uint sweep, __global uint* sweepResidual) {
    if (sweep > 0u && !(as_float(sweepResidual[sweep - 1u]) > RUBBLE_PUSH_TOLERANCE)) return;
    __local uint largest;
    groupClear(&largest, 1u);
    const ElementRange range = elementRange(first, count, mode, blockStarts);
    float residual = 0.0f;
    const uint passes = slotPasses(mode, blockStarts);
    for (uint pass = 0u; pass < passes; ++pass)
        for (uint i = range.begin; i < range.end; i += range.step)
            residual = fmax(residual, pushElement(elements[range.first + i], normalRows, impulses,
                                                  pushed, push, relaxation, passSlot(mode, pass)));
    if (residual > 0.0f) atomic_max(&largest, as_uint(residual));
    if (groupDone() && largest > 0u) atomic_max(&sweepResidual[sweep], largest);
}

// What the layer pass marks on a body: it carries a heavy load, or it is in a joint.
#define RUBBLE_LAYER_LOADED 1u
#define RUBBLE_LAYER_JOINED 2u

// The row `entry` of the layer pass's lists names: element index << 2 | point.
static uint layerRow(const uint entry, __global const PgsElement* elements) {
    return elements[entry >> 2].normal[entry & 3u];
}

// The layer pass (shock propagation; PgsSolver's solveLayers, then its rows on the split pass's
// velocities as solvePushes ends), after the sweeps of a step whose summaries found moving bodies
// RUBBLE_LAYER_MASS_RATIO times apart in mass. It walks every row and body in order, so it runs
// on one work-item: each body's layer (0 for a body that does not move, else one more than the
// lowest it touches through a row), the rows between layers whose upper body is that much
// heavier than the lower one or carries such a load (top down, a stable counting sort by the
// lower layer), then once more from the bottom up, each row moving its upper body only
// (solvePgsNormalOntoItem): on the velocities toward the row's target, and, when the split pass
// ran (`pushes`, and some row pushed), on the push velocities toward its push target for the
// rows that push or touch a pushed body. Rows of jointed bodies take no part. Scratch: layer and
// loaded per body, lists and the histogram of lower layers (bodies + 1 words).
__kernel void layerPgs(const uint count, __global const PgsElement* elements,
                       __global const PgsNormalRow* normalRows, __global const float4* impulses,
                       __global const JacobiBody* bodies, const uint bodyCount,
                       __global const PgsJoint* joints, const uint jointCount,
                       __global BodyVelocity* velocities, const uint pushes,
                       __global const uint* pushed, __global BodyVelocity* push,
                       __global const uint* status, __global uint* layer, __global uint* loaded,
                       __global uint* rows, __global uint* sorted, __global uint* histogram) {
    if (get_global_id(0) != 0u) return;
    for (uint i = 0; i < bodyCount; ++i) loaded[i] = 0u;
    for (uint j = 0; j < jointCount; ++j)
        loaded[joints[j].a] = loaded[joints[j].b] = RUBBLE_LAYER_JOINED;
    // Most steps have no such pair outside the joints: nothing to do.
    int any = 0;
    for (uint i = 0; i < count && !any; ++i) {
        const PgsElement e = elements[i];
        if (e.id & RUBBLE_PGS_JOINT_ELEMENT || loaded[e.a] || loaded[e.b]) continue;
        for (uint k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k) {
            const PgsNormalRow r = normalRows[e.normal[k]];
            any = any || heavyOverItem(r.speeds.z, r.speeds.w) ||
                  heavyOverItem(r.speeds.w, r.speeds.z);
        }
    }
    if (!any) return;
    // Layers up from the bodies that do not move, until no row lowers one.
    for (uint i = 0; i < bodyCount; ++i)
        layer[i] = jointInverseMassItem(bodies[i]) > 0.0f ? RUBBLE_NO_LAYER : 0u;
    for (int changed = 1; changed;) {
        changed = 0;
        for (uint i = 0; i < count; ++i) {
            const PgsElement e = elements[i];
            if (e.id & RUBBLE_PGS_JOINT_ELEMENT || (e.rows & RUBBLE_PGS_POINTS) == 0u) continue;
            if (layer[e.a] != RUBBLE_NO_LAYER && layer[e.a] + 1u < layer[e.b]) {
                layer[e.b] = layer[e.a] + 1u;
                changed = 1;
            }
            if (layer[e.b] != RUBBLE_NO_LAYER && layer[e.b] + 1u < layer[e.a]) {
                layer[e.a] = layer[e.b] + 1u;
                changed = 1;
            }
        }
    }
    // The rows between two layers, outside the joints, by lower layer from the top down.
    uint n = 0, top = 0;
    for (uint i = 0; i < count; ++i) {
        const PgsElement e = elements[i];
        if (e.id & RUBBLE_PGS_JOINT_ELEMENT) continue;
        const uint la = layer[e.a], lb = layer[e.b];
        if (la == lb || la == RUBBLE_NO_LAYER || lb == RUBBLE_NO_LAYER ||
            loaded[e.a] == RUBBLE_LAYER_JOINED || loaded[e.b] == RUBBLE_LAYER_JOINED)
            continue;
        for (uint k = 0; k < (e.rows & RUBBLE_PGS_POINTS); ++k) rows[n++] = i << 2 | k;
        top = max(top, min(la, lb));
    }
    for (uint l = 0; l <= top; ++l) histogram[l] = 0u;
    for (uint i = 0; i < n; ++i) {
        const PgsElement e = elements[rows[i] >> 2];
        ++histogram[min(layer[e.a], layer[e.b])];
    }
    // Starts, highest layer first; then placed in order (stable).
    uint start = 0;
    for (uint l = top + 1u; l-- > 0u;) {
        const uint c = histogram[l];
        histogram[l] = start;
        start += c;
    }
    for (uint i = 0; i < n; ++i) {
        const PgsElement e = elements[rows[i] >> 2];
        sorted[histogram[min(layer[e.a], layer[e.b])]++] = rows[i];
    }
    // Top down: a row takes part when its upper body is that much heavier than its lower one,
    // or carries such a load; its lower body then carries it.
    uint kept = 0;
    for (uint i = 0; i < n; ++i) {
        const uint entry = sorted[i];
        const PgsElement e = elements[entry >> 2];
        const PgsNormalRow r = normalRows[layerRow(entry, elements)];
        const int upperIsB = layer[e.b] > layer[e.a];
        const uint up = upperIsB ? e.b : e.a, down = upperIsB ? e.a : e.b;
        const float upInverse = upperIsB ? r.speeds.w : r.speeds.z;
        const float downInverse = upperIsB ? r.speeds.z : r.speeds.w;
        if (!heavyOverItem(upInverse, downInverse) && loaded[up] != RUBBLE_LAYER_LOADED) continue;
        loaded[down] = RUBBLE_LAYER_LOADED;
        rows[kept++] = entry;
    }
    // Bottom up, each row stopping its upper body against the lower one.
    const int pushPass = pushes && status[RUBBLE_STATUS_PUSHED];
    for (uint i = kept; i-- > 0u;) {
        const uint entry = rows[i];
        const PgsElement e = elements[entry >> 2];
        const uint row = layerRow(entry, elements);
        const PgsNormalRow r = normalRows[row];
        const float4 l = impulses[row];
        const int upperIsB = layer[e.b] > layer[e.a];
        BodyVelocityPair v = loadPair(e.a, e.b, velocities);
        PgsUpdate u = solvePgsNormalOntoItem(r, v, upperIsB, r.speeds.x, l.x);
        if (upperIsB) velocities[e.b] = u.v.b;
        else velocities[e.a] = u.v.a;
        if (!pushPass || (r.speeds.y <= 0.0f && !pushed[e.a] && !pushed[e.b])) continue;
        v = loadPair(e.a, e.b, push);
        u = solvePgsNormalOntoItem(r, v, upperIsB, r.speeds.y, l.w);
        if (upperIsB) push[e.b] = u.v.b;
        else push[e.a] = u.v.a;
    }
}

// After integratePositions, when some row pushed: every body that moved in the solve is moved
// by dt times its push velocity, and its velocities follow from its momenta at the new
// orientation (PgsSolver::solvePositions).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
applyPushes(const uint count, __global const uint* status, __global const JacobiBody* bodies,
            __global const BodyVelocity* push, __global const BodyMomentum* momenta,
            __global const BodyMass* masses, __global BodyPose* poses,
            __global BodyVelocity* velocities, const float dt) {
    const uint i = get_global_id(0);
    if (i >= count || !status[RUBBLE_STATUS_PUSHED]) return;
    if (!movesInSolveItem(bodies[i])) return;
    const BodyVelocity v = push[i];
    BodyPose pose = poses[i];
    pose.position = add4(pose.position, scale4(v.linear, dt));
    pose.orientation = quatIntegrate(pose.orientation, v.angular, dt);
    poses[i] = pose;
    velocities[i] = velocityFromMomentumItem(momenta[i], masses[i], pose.orientation);
}
