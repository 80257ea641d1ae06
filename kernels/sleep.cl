// kernels/sleep.cl: entry points of the device's sleeping, each body by itself (particles, or SAT
// with --body-sleep): the wake before the rows (wakeTouched, wakeTouchedPairs) and stage
// sleepBodies after integratePositions, where each contact and joint tells its bodies whether a
// neighbour is restless or fast and each dynamic body updates its sleep. SAT's islands are
// kernels/islands.cl. The math is in rubble/shared/sleep.h; the CPU twins in
// host/dynamics/sleep.cpp.
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/contact_row.h"
#include "rubble/shared/group.h"
#include "rubble/shared/narrow_phase.h"
#include "rubble/shared/pgs_joint.h"
#include "rubble/shared/sleep.h"

// Wakes body `wake` (RUBBLE_NO_BODY: none) before the solve, its slow time starting again, and
// counts it; in collision round `collisionRound` > 0 marks it with the round (its restless
// word), from which it wakes others in later rounds. A body another work-item woke first is
// left alone.
static void wakeBody(const uint wake, const uint collisionRound, __global uint* flags,
                     __global float* slowFor, __global uint* restless, __global uint* status) {
    if (wake == RUBBLE_NO_BODY) return;
    const uint before = atomic_and(&flags[wake], ~RUBBLE_BODY_ASLEEP);
    if (!(before & RUBBLE_BODY_ASLEEP)) return;
    slowFor[wake] = 0.0f;
    if (collisionRound > 0u)
        atomic_or(&restless[wake], collisionRound << RUBBLE_RESTLESS_WOKEN_SHIFT);
    atomic_inc(&status[RUBBLE_STATUS_WOKEN]);
}

// A contact of a sleeping body with a waking one (wakesBeforeSolveItem, on the velocities before
// this step's forces) wakes it now, its slow time starting again. In round `collisionRound` > 0 of
// the SAT collision (wakesInRoundItem) a body woken in an earlier round wakes the sleeping bodies
// it touches too, and the body woken here is marked with the round in its restless word; a body
// woken in this round wakes nobody in it, so the result does not depend on the order of the
// contacts. Round 0 (particles) reads and writes no marks.
static void wakeTouchedBodies(const uint a, const uint b, __global const BodyVelocity* approach,
                              __global uint* flags, __global float* slowFor,
                              __global uint* restless, const uint collisionRound,
                              __global uint* status) {
    // Read as atomics: another work-item may be waking either body (wakeBody). Either value
    // gives the same decision: a body woken in this launch wakes nobody in it (its approach
    // velocity is a sleeping body's, zero, and its round mark is not an earlier round's).
    const uint fa = atomic_or(&flags[a], 0u), fb = atomic_or(&flags[b], 0u);
    const uint ra = collisionRound > 0u ? atomic_or(&restless[a], 0u) : 0u;
    const uint rb = collisionRound > 0u ? atomic_or(&restless[b], 0u) : 0u;
    uint wake = RUBBLE_NO_BODY;
    if (wakesInRoundItem(fa, fb, approach[b], rb, collisionRound)) wake = a;
    if (wakesInRoundItem(fb, fa, approach[a], ra, collisionRound)) wake = b;
    wakeBody(wake, collisionRound, flags, slowFor, restless, status);
}

// A contact or joint marks both of its bodies from the other's velocity after the step
// (restless was zeroed by the last step's sleepBodies, or at load).
static void markRestlessBodies(const uint a, const uint b,
                               __global const BodyVelocity* velocities, __global const uint* flags,
                               __global uint* restless) {
    const uint fa = flags[a], fb = flags[b];
    const uint toA = restlessFromContactItem(fa, fb, velocities[b]);
    const uint toB = restlessFromContactItem(fb, fa, velocities[a]);
    const uint fixed = RUBBLE_BODY_STATIC | RUBBLE_BODY_KINEMATIC;
    if (toA && !(fa & fixed)) atomic_or(&restless[a], toA);
    if (toB && !(fb & fixed)) atomic_or(&restless[b], toB);
}

// Stage wakeTouched, after collideParticles and before the rows: each contact's bodies.
__kernel void wakeTouched(__global uint* status, __global const ParticleContact* contacts,
                          __global const BodyVelocity* approach, __global uint* flags,
                          __global float* slowFor) {
    const uint n = liveContactsItem(status[RUBBLE_STATUS_CONTACTS], status[RUBBLE_STATUS_CAPACITY]);
    for (uint r = get_global_id(0); r < n; r += get_global_size(0))
        wakeTouchedBodies(contacts[r].a, contacts[r].b, approach, flags, slowFor, 0, 0u, status);
}

// Stage wake for SAT, after the narrow phase and before the rows: each pair with points, in
// round `collisionRound` (1, 2, ...) of the step's collision. The host collides again when this
// woke a body: its pairs with other sleeping bodies were not found, and those it touches wake in
// the next round.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
wakeTouchedPairs(const uint capacity, __global const uint* pairCount,
                 __global const BodyPairRecord* pairs, __global const ContactManifold* manifolds,
                 __global const BodyVelocity* approach, __global uint* flags,
                 __global float* slowFor, __global uint* restless, const uint collisionRound,
                 __global uint* status) {
    const uint n = min(pairCount[0], capacity);
    const ItemRange r = itemRange(n);
    for (uint p = r.first; p < r.end; p += r.step)
        if (manifolds[p].count > 0u)
            wakeTouchedBodies(pairs[p].a, pairs[p].b, approach, flags, slowFor, restless,
                              collisionRound, status);
}

// The wake through resting piles, SAT on the device: in round `collisionRound` of the step's
// collision, each of last step's entries that held impulses (its pairs and the still pairs it
// carried, markStillPairs in kernels/pgs_still_pairs.cl: bodies that touched as they came to
// rest) wakes its sleeping body when the other was woken in an earlier round. The host repeats
// it, a round a launch, until a round wakes none, so that a hit wakes the sleeping bodies it
// reaches through touching ones before the solve, as the CPU wakes an island as one.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
wakeStillPairs(const uint previousCapacity, __global const uint* previousCount,
               __global const BodyPairRecord* previousPairs,
               __global const uint* previousImpulseCount, __global uint* flags,
               __global float* slowFor, __global uint* restless, const uint collisionRound,
               __global uint* status) {
    const uint n = keptPairsItem(previousCount, previousCapacity);
    const ItemRange r = itemRange(n);
    for (uint q = r.first; q < r.end; q += r.step) {
        if (previousImpulseCount[q] == 0u) continue;
        const BodyPairRecord pair = previousPairs[q];
        // Read as atomics: another work-item may be waking either body (wakeBody). Either
        // value gives the same decision: a body woken in this round wakes nobody in it.
        const uint fa = atomic_or(&flags[pair.a], 0u), fb = atomic_or(&flags[pair.b], 0u);
        const uint ra = atomic_or(&restless[pair.a], 0u), rb = atomic_or(&restless[pair.b], 0u);
        uint wake = RUBBLE_NO_BODY;
        if ((fa & RUBBLE_BODY_ASLEEP) && wokenBeforeItem(fb, rb, collisionRound)) wake = pair.a;
        if ((fb & RUBBLE_BODY_ASLEEP) && wokenBeforeItem(fa, ra, collisionRound)) wake = pair.b;
        wakeBody(wake, collisionRound, flags, slowFor, restless, status);
    }
}

// Restless marks from every row of the Jacobi solver.
__kernel void markRestless(__global const uint* status, __global const ContactRow* rows,
                           __global const BodyVelocity* velocities, __global const uint* flags,
                           __global uint* restless) {
    const uint n = liveContactsItem(status[RUBBLE_STATUS_CONTACTS], status[RUBBLE_STATUS_CAPACITY]);
    for (uint r = get_global_id(0); r < n; r += get_global_size(0))
        markRestlessBodies(rows[r].a, rows[r].b, velocities, flags, restless);
}

// Restless marks from every SAT pair with contact points.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
markRestlessPairs(const uint capacity, __global const uint* pairCount,
                  __global const BodyPairRecord* pairs, __global const ContactManifold* manifolds,
                  __global const BodyVelocity* velocities, __global const uint* flags,
                  __global uint* restless) {
    const uint n = min(pairCount[0], capacity);
    const ItemRange r = itemRange(n);
    for (uint p = r.first; p < r.end; p += r.step)
        if (manifolds[p].count > 0u)
            markRestlessBodies(pairs[p].a, pairs[p].b, velocities, flags, restless);
}

// Restless marks from every joint, as from a contact.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
markRestlessJoints(const uint count, __global const PgsJoint* joints,
                   __global const BodyVelocity* velocities, __global const uint* flags,
                   __global uint* restless) {
    const uint j = get_global_id(0);
    if (j < count) markRestlessBodies(joints[j].a, joints[j].b, velocities, flags, restless);
}

// Each dynamic body's sleep for the step; a body falling asleep stops (velocities and momenta
// zero). The group's counts of sleeping and woken bodies go to the status block.
__kernel void sleepBodies(const uint count, __global uint* status, __global uint* flags,
                          __global BodyVelocity* velocities, __global BodyMomentum* momenta,
                          __global float* slowFor, __global uint* restless, const float dt) {
    __local uint totals[2]; // the group's bodies asleep, woken
    const uint i = get_global_id(0);
    // Every work-item reaches both barriers; a step whose contacts overflowed changes nothing.
    const int aborted = status[RUBBLE_STATUS_CONTACTS] > status[RUBBLE_STATUS_CAPACITY];
    groupClear(totals, 2u);
    if (!aborted && i < count && !(flags[i] & (RUBBLE_BODY_STATIC | RUBBLE_BODY_KINEMATIC))) {
        SleepRecord s;
        s.flags = flags[i];
        s.slowFor = slowFor[i];
        const SleepRecord next = sleepItem(s, restless[i], slowBodyItem(velocities[i]), dt);
        if ((next.flags & RUBBLE_BODY_ASLEEP) && !(s.flags & RUBBLE_BODY_ASLEEP)) {
            const float4 zero = vec4(0.0f, 0.0f, 0.0f);
            velocities[i].linear = zero;
            velocities[i].angular = zero;
            momenta[i].linear = zero;
            momenta[i].angular = zero;
        }
        if (!(next.flags & RUBBLE_BODY_ASLEEP) && (s.flags & RUBBLE_BODY_ASLEEP))
            atomic_inc(&totals[1]);
        if (next.flags & RUBBLE_BODY_ASLEEP) atomic_inc(&totals[0]);
        flags[i] = next.flags;
        slowFor[i] = next.slowFor;
        restless[i] = 0u;
    }
    if (!groupDone() || aborted) return;
    if (totals[0] > 0u) atomic_add(&status[RUBBLE_STATUS_ASLEEP], totals[0]);
    if (totals[1] > 0u) atomic_add(&status[RUBBLE_STATUS_WOKEN], totals[1]);
}

// Jointed bodies sleep and wake by joint group (bodies joined through dynamic bodies), as the
// CPU's islands do: a body alone at the end of a joint would otherwise fall asleep under a
// restless neighbour's momentary pause and leave it pulling at a wall. Before sleepBodies, each
// member votes whether it would stay awake (bit 1 of its group's word); then every member of
// such a group is marked restless, so that none falls asleep.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
voteJointGroups(const uint count, __global const uint* jointBodies, __global const uint* groupOf,
                __global const uint* flags, __global const float* slowFor,
                __global const uint* restless, __global const BodyVelocity* velocities,
                const float dt, __global uint* groupVotes) {
    const uint k = get_global_id(0);
    if (k >= count || groupOf[k] == RUBBLE_NO_GROUP) return;
    const uint i = jointBodies[k];
    SleepRecord s;
    s.flags = flags[i];
    s.slowFor = slowFor[i];
    const SleepRecord next = sleepItem(s, restless[i], slowBodyItem(velocities[i]), dt);
    if (!(next.flags & RUBBLE_BODY_ASLEEP)) atomic_or(&groupVotes[groupOf[k]], 1u);
}

__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
holdJointGroups(const uint count, __global const uint* jointBodies, __global const uint* groupOf,
                __global const uint* groupVotes, __global uint* restless) {
    const uint k = get_global_id(0);
    if (k >= count || groupOf[k] == RUBBLE_NO_GROUP) return;
    if (groupVotes[groupOf[k]] & 1u) atomic_or(&restless[jointBodies[k]], RUBBLE_RESTLESS_NEIGHBOUR);
}

// After sleepBodies: pass 0 marks the groups with an awake member (bit 2), pass 1 wakes the
// sleeping members of those groups, so that a group wakes as one. Before the solve (SAT, after
// wakeTouchedPairs) pass 2 wakes them as pass 1 does, without the asleep count, which is the
// step's end's, and marks them with the collision round (`collisionRound` > 0), so that the
// wake goes on from every member of the group.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
wakeJointGroups(const uint count, __global const uint* jointBodies, __global const uint* groupOf,
                __global uint* flags, __global float* slowFor, __global uint* groupVotes,
                __global uint* restless, const uint pass, const uint collisionRound,
                __global uint* status) {
    const uint k = get_global_id(0);
    if (k >= count || groupOf[k] == RUBBLE_NO_GROUP) return;
    const uint i = jointBodies[k], g = groupOf[k];
    const uint f = flags[i];
    if (pass == 0u) {
        if (!(f & RUBBLE_BODY_ASLEEP)) atomic_or(&groupVotes[g], 2u);
        return;
    }
    if (!(f & RUBBLE_BODY_ASLEEP) || !(groupVotes[g] & 2u)) return;
    flags[i] = f & ~RUBBLE_BODY_ASLEEP;
    slowFor[i] = 0.0f;
    if (pass == 2u && collisionRound > 0u)
        atomic_or(&restless[i], collisionRound << RUBBLE_RESTLESS_WOKEN_SHIFT);
    if (pass == 1u) atomic_dec(&status[RUBBLE_STATUS_ASLEEP]);
    atomic_inc(&status[RUBBLE_STATUS_WOKEN]);
}
