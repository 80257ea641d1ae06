// kernels/jacobi.cl: entry points of OpenCL stage 5 (solveJacobi): per-body row lists, warm
// start, rows, the iteration's two halves (rows from velocities, velocities from rows), and the
// impulses on the host's bodies. The math is in rubble/shared/contact_row.h; the CPU twins in
// host/dynamics/jacobi.cpp. Kernels over contacts stride through the count the status holds.
#include "rubble/shared/contact_row.h"

#define RUBBLE_LIVE_CONTACTS(status)                                                               \
    liveContactsItem(status[RUBBLE_STATUS_CONTACTS], status[RUBBLE_STATUS_CAPACITY])

// bodyCount was zeroed; each contact counts once on each of its listed bodies.
__kernel void countBodyContacts(__global const uint* status,
                                __global const ParticleContact* contacts,
                                __global const uint* flags, __global uint* bodyCount) {
    const uint n = RUBBLE_LIVE_CONTACTS(status);
    for (uint r = get_global_id(0); r < n; r += get_global_size(0)) {
        const ParticleContact c = contacts[r];
        if (listedBodyItem(flags[c.a])) atomic_inc(&bodyCount[c.a]);
        if (listedBodyItem(flags[c.b])) atomic_inc(&bodyCount[c.b]);
    }
}

// cursor starts as a copy of bodyStart; entries are 2 row + side, in any order (sorted next).
__kernel void fillBodyLists(__global const uint* status, __global const ParticleContact* contacts,
                            __global const uint* flags, __global uint* cursor,
                            __global uint* bodyList) {
    const uint n = RUBBLE_LIVE_CONTACTS(status);
    for (uint r = get_global_id(0); r < n; r += get_global_size(0)) {
        const ParticleContact c = contacts[r];
        if (listedBodyItem(flags[c.a])) bodyList[atomic_inc(&cursor[c.a])] = 2u * r;
        if (listedBodyItem(flags[c.b])) bodyList[atomic_inc(&cursor[c.b])] = 2u * r + 1u;
    }
}

// Each body's entries in row order (insertion sort: lists are short), so that its sums run in
// the same order on every run and on the CPU.
__kernel void sortBodyLists(const uint bodies, __global const uint* bodyStart,
                            __global uint* bodyList) {
    const uint b = get_global_id(0);
    if (b >= bodies) return;
    const uint begin = bodyStart[b], end = bodyStart[b + 1];
    for (uint i = begin + 1; i < end; ++i) {
        const uint v = bodyList[i];
        uint j = i;
        while (j > begin && bodyList[j - 1] > v) {
            bodyList[j] = bodyList[j - 1];
            --j;
        }
        bodyList[j] = v;
    }
}

// Last step's contacts chained per particle (head was filled with RUBBLE_EMPTY_CELL); a
// contact's key (particleA, featureB) is unique, so the chain order does not matter.
__kernel void linkPrevious(const uint count, __global const ParticleContact* previous,
                           __global uint* head, __global uint* next) {
    const uint r = get_global_id(0);
    if (r >= count) return;
    next[r] = atomic_xchg(&head[previous[r].particleA], r);
}

// What the rows and gathers need of each body this step; a sleeping body is a wall.
__kernel void prepareJacobiBodies(const uint count, __global const BodyMass* masses,
                                  __global const uint* flags, __global const BodyPose* poses,
                                  __global JacobiBody* jacobiBodies) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    BodyMass m = masses[i];
    if (flags[i] & RUBBLE_BODY_ASLEEP) m = wallMassItem(m);
    jacobiBodies[i] = jacobiBodyItem(m, poses[i].orientation);
}

// approach: the bodies' velocities before this step's forces, for restitution.
__kernel void buildJacobiRows(__global const uint* status,
                              __global const ParticleContact* contacts,
                              __global const BodyPose* poses,
                              __global const BodyVelocity* approach,
                              __global const JacobiBody* jacobiBodies,
                              __global const float4* surfaces, __global const uint* bodyCount,
                              const SolverParams params, const uint warmStart,
                              __global const uint* head, __global const uint* next,
                              __global const ParticleContact* previous,
                              __global const ContactRow* previousRows,
                              __global ContactRow* rows) {
    const uint n = RUBBLE_LIVE_CONTACTS(status);
    for (uint r = get_global_id(0); r < n; r += get_global_size(0)) {
        const ParticleContact c = contacts[r];
        // Last step's impulses when the same two features touched.
        float4 warm = vec4(0.0f, 0.0f, 0.0f);
        if (warmStart) {
            for (uint p = head[c.particleA]; p != RUBBLE_EMPTY_CELL; p = next[p]) {
                if (previous[p].featureB == c.featureB && previous[p].b == c.b) {
                    warm = previousRows[p].lambda;
                    break;
                }
            }
        }
        rows[r] = contactRowFromJacobiItem(c, poses[c.a].position, poses[c.b].position,
                                           approach[c.a], approach[c.b], jacobiBodies[c.a],
                                           jacobiBodies[c.b], surfaces[c.a], surfaces[c.b],
                                           bodyCount[c.a], bodyCount[c.b], params, warm);
    }
}

// The first half of an iteration: each row's impulses from the last iteration's velocities,
// and the impulse they put on body b, for the gather. On the last sweep, the largest change
// goes to the status buffer as the residual.
__kernel void solveJacobiRows(__global uint* status, __global ContactRow* rows,
                              __global const BodyVelocity* velocities, const float relaxation,
                              const uint lastSweep, __global float4* impulses) {
    const uint n = RUBBLE_LIVE_CONTACTS(status);
    for (uint r = get_global_id(0); r < n; r += get_global_size(0)) {
        ContactRow row = rows[r];
        const float4 next = solveContactItem(row, velocities[row.a], velocities[row.b],
                                             relaxation);
        if (lastSweep)
            atomic_max(&status[RUBBLE_STATUS_RESIDUAL],
                       as_uint(impulseChangeItem(row.lambda, next)));
        row.lambda = next;
        rows[r].lambda = next;
        impulses[r] = rowImpulseItem(row);
    }
}

// The gather before the first sweep (warm-started impulses, or the dense solver's): each active
// body's velocity from the solve's start and its rows, read whole; it keeps each entry's arm
// (the contact point from the body's centre of mass) for the later gathers.
__kernel void gatherJacobiRows(const uint bodies, __global const ContactRow* rows,
                               __global const uint* bodyStart, __global const uint* bodyList,
                               __global const BodyVelocity* before,
                               __global const JacobiBody* jacobiBodies,
                               __global const uint* flags, __global BodyVelocity* velocities,
                               __global float4* arms) {
    const uint b = get_global_id(0);
    if (b >= bodies) return;
    if (!activeBodyItem(flags[b])) return;
    const JacobiBody j = jacobiBodies[b];
    const float inverseMass = j.inverseInertiaWorld.r0.w;
    if (inverseMass == 0.0f) return;
    float4 linear = vec4(0.0f, 0.0f, 0.0f), angular = vec4(0.0f, 0.0f, 0.0f);
    const uint end = bodyStart[b + 1];
    for (uint e = bodyStart[b]; e < end; ++e) {
        const uint entry = bodyList[e];
        const ContactRow row = rows[entry >> 1];
        const float4 arm = (entry & 1u) ? row.rB : row.rA;
        arms[e] = arm;
        const BodyImpulse i = impulseOnBodyItem(rowImpulseItem(row), arm, entry & 1u);
        linear = add4(linear, i.linear);
        angular = add4(angular, i.angular);
    }
    velocities[b] = applyImpulseSumItem(before[b], linear, angular, inverseMass,
                                        j.inverseInertiaWorld);
}

// The second half: each active body's velocity from the solve's start and the impulses of its
// rows (solveJacobiRows), 32 bytes per entry instead of the whole row.
__kernel void gatherJacobi(const uint bodies, __global const float4* impulses,
                           __global const uint* bodyStart, __global const uint* bodyList,
                           __global const float4* arms, __global const BodyVelocity* before,
                           __global const JacobiBody* jacobiBodies, __global const uint* flags,
                           __global BodyVelocity* velocities) {
    const uint b = get_global_id(0);
    if (b >= bodies) return;
    if (!activeBodyItem(flags[b])) return;
    const JacobiBody j = jacobiBodies[b];
    const float inverseMass = j.inverseInertiaWorld.r0.w;
    if (inverseMass == 0.0f) return;
    float4 linear = vec4(0.0f, 0.0f, 0.0f), angular = vec4(0.0f, 0.0f, 0.0f);
    const uint end = bodyStart[b + 1];
    for (uint e = bodyStart[b]; e < end; ++e) {
        const uint entry = bodyList[e];
        const BodyImpulse i = impulseOnBodyItem(impulses[entry >> 1], arms[e], entry & 1u);
        linear = add4(linear, i.linear);
        angular = add4(angular, i.angular);
    }
    velocities[b] = applyImpulseSumItem(before[b], linear, angular, inverseMass,
                                        j.inverseInertiaWorld);
}

// Two-way coupling: the summed impulse of its rows on each of the host's bodies (about its centre
// of mass as placed this step), which the host applies in the next step.
__kernel void gatherObstacleImpulses(const uint count, __global const uint* obstacles,
                                     __global const ContactRow* rows,
                                     __global const uint* bodyStart,
                                     __global const uint* bodyList,
                                     __global BodyImpulse* impulses) {
    const uint k = get_global_id(0);
    if (k >= count) return;
    const uint b = obstacles[k];
    BodyImpulse sum;
    sum.linear = vec4(0.0f, 0.0f, 0.0f);
    sum.angular = vec4(0.0f, 0.0f, 0.0f);
    const uint end = bodyStart[b + 1];
    for (uint e = bodyStart[b]; e < end; ++e) {
        const uint entry = bodyList[e];
        const BodyImpulse i = rowImpulseOnBodyItem(rows[entry >> 1], entry & 1u);
        sum.linear = add4(sum.linear, i.linear);
        sum.angular = add4(sum.angular, i.angular);
    }
    impulses[k] = sum;
}
