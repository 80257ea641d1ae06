// kernels/jacobi.cl: entry points of OpenCL stage 5 (solveJacobi): per-body row lists, warm
// start, rows, and the iteration's two halves (rows from velocities, velocities from rows).
// The math is in rubble/shared/contact_row.h; the CPU twins in host/dynamics/jacobi.cpp.
#include "rubble/shared/contact_row.h"

// bodyCount was zeroed; each contact counts once on each of its dynamic bodies.
__kernel void countBodyContacts(const uint count, __global const ParticleContact* contacts,
                                __global const BodyMass* masses, __global uint* bodyCount) {
    const uint r = get_global_id(0);
    if (r >= count) return;
    const ParticleContact c = contacts[r];
    if (masses[c.a].inverseMass != 0.0f) atomic_inc(&bodyCount[c.a]);
    if (masses[c.b].inverseMass != 0.0f) atomic_inc(&bodyCount[c.b]);
}

// cursor starts as a copy of bodyStart; entries are 2 row + side, in any order (sorted next).
__kernel void fillBodyLists(const uint count, __global const ParticleContact* contacts,
                            __global const BodyMass* masses, __global uint* cursor,
                            __global uint* bodyList) {
    const uint r = get_global_id(0);
    if (r >= count) return;
    const ParticleContact c = contacts[r];
    if (masses[c.a].inverseMass != 0.0f) bodyList[atomic_inc(&cursor[c.a])] = 2u * r;
    if (masses[c.b].inverseMass != 0.0f) bodyList[atomic_inc(&cursor[c.b])] = 2u * r + 1u;
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

__kernel void buildJacobiRows(const uint count, __global const ParticleContact* contacts,
                              __global const BodyPose* poses,
                              __global const BodyVelocity* velocities,
                              __global const BodyMass* masses, __global const float4* surfaces,
                              __global const uint* bodyCount, const SolverParams params,
                              const uint warmStart, __global const uint* head,
                              __global const uint* next,
                              __global const ParticleContact* previous,
                              __global const ContactRow* previousRows,
                              __global ContactRow* rows) {
    const uint r = get_global_id(0);
    if (r >= count) return;
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
    rows[r] = contactRowFromContactItem(c, poses[c.a], poses[c.b], velocities[c.a],
                                        velocities[c.b], masses[c.a], masses[c.b], surfaces[c.a],
                                        surfaces[c.b], bodyCount[c.a], bodyCount[c.b], params,
                                        warm);
}

// The first half of an iteration: each row's impulses from the last iteration's velocities.
// On the last sweep, the largest change goes to the status buffer as the residual.
__kernel void solveJacobiRows(const uint count, __global ContactRow* rows,
                              __global const BodyVelocity* velocities, const float relaxation,
                              const uint lastSweep, __global uint* status) {
    const uint r = get_global_id(0);
    if (r >= count) return;
    const ContactRow row = rows[r];
    const float4 next = solveContactItem(row, velocities[row.a], velocities[row.b], relaxation);
    rows[r].lambda = next;
    if (lastSweep)
        atomic_max(&status[RUBBLE_STATUS_RESIDUAL], as_uint(impulseChangeItem(row.lambda, next)));
}

// The second half: each dynamic body's velocity from the solve's start and its rows.
__kernel void gatherJacobi(const uint bodies, __global const ContactRow* rows,
                           __global const uint* bodyStart, __global const uint* bodyList,
                           __global const BodyVelocity* before, __global const BodyMass* masses,
                           __global const BodyPose* poses, __global BodyVelocity* velocities) {
    const uint b = get_global_id(0);
    if (b >= bodies) return;
    const BodyMass m = masses[b];
    if (m.inverseMass == 0.0f) return;
    float4 linear = vec4(0.0f, 0.0f, 0.0f), angular = vec4(0.0f, 0.0f, 0.0f);
    const uint end = bodyStart[b + 1];
    for (uint e = bodyStart[b]; e < end; ++e) {
        const uint entry = bodyList[e];
        const BodyImpulse i = rowImpulseOnBodyItem(rows[entry >> 1], entry & 1u);
        linear = add4(linear, i.linear);
        angular = add4(angular, i.angular);
    }
    velocities[b] = applyImpulseSumItem(before[b], linear, angular, m.inverseMass,
                                        inverseInertiaWorldItem(m, poses[b].orientation));
}
