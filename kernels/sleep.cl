// kernels/sleep.cl: entry points of the device's sleeping. Each body by itself (particles, or SAT
// with --body-sleep): the wake before the rows (wakeTouched, wakeTouchedPairs) and stage
// sleepBodies after integratePositions, where each contact and joint tells its bodies whether a
// neighbour is restless or fast and each dynamic body updates its sleep. By islands (SAT): the
// CPU's wakeIslands after each collision round's summaries and its updateSleep at the end of the
// step, the islands found by a concurrent union-find over the pairs with rows and the joints. The
// math is in rubble/shared/sleep.h; the CPU twins in host/dynamics/sleep.cpp and islands.cpp.
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/contact_row.h"
#include "rubble/shared/group.h"
#include "rubble/shared/narrow_phase.h"
#include "rubble/shared/pgs_joint.h"
#include "rubble/shared/pgs_row.h"
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

// ---- Islands (SAT): the CPU's wakeIslands and updateSleep (host/dynamics/islands.cpp) ----

// A body that islands join: dynamic (a positive inverse mass), as on the CPU.
static int islandBody(__global const BodyMass* masses, const uint i) {
    return masses[i].inverseMass > 0.0f;
}

// The root of node `v`'s tree: the smallest node of its island found so far. Plain volatile
// reads, not atomics: every work-item's walk ends at the few roots of a large island, and an
// atomic read would take their cache lines from core to core. A read that misses another
// work-item's hook still names an ancestor, which is in the same island (uniteNodes' swap only
// hooks a node that is still a root). Oclgrind reports such a read beside a hook of the same word
// as a data race.
static uint islandRoot(volatile __global uint* labels, uint v) {
    uint up = labels[v];
    while (up != v) {
        v = up;
        up = labels[v];
    }
    return v;
}

// Joins the islands of nodes `u` and `v`: the larger root is hooked under the smaller, if it is
// still a root (else another work-item hooked it first, and the roots are found again). Every
// link points to a smaller node, so the trees have no cycles and each root is its island's
// smallest node, the CPU's UnionFind root; one launch over the edges joins them all.
static void uniteNodes(volatile __global uint* labels, uint u, uint v) {
    for (;;) {
        u = islandRoot(labels, u);
        v = islandRoot(labels, v);
        if (u == v) return;
        const uint low = min(u, v), high = max(u, v);
        if (atomic_cmpxchg(&labels[high], high, low) == high) return;
        u = low;
        v = high;
    }
}

// Whether a round's pair overflowed its buffers: the wake waits for the round that finds them all.
static int pairsOverflow(const uint capacity, __global const uint* pairCount) {
    return pairCount[0] > capacity;
}

// Marks the sleeping body `i` to wake (RUBBLE_ISLAND_WAKE_*): alone when it sleeps in no group,
// else with its group.
static void markIslandWake(__global const uint* group, __global uint* marks, const uint i) {
    const uint g = group[i];
    if (g == RUBBLE_NO_ISLAND)
        atomic_or(&marks[i], RUBBLE_ISLAND_WAKE_BODY);
    else
        atomic_or(&marks[g], RUBBLE_ISLAND_WAKE_GROUP);
}

// The CPU's touch in wakeIslands: a restless body marks the sleeping body it touches; both take
// part (dynamic, or restless: a moving kinematic body).
static void touchIslands(const uint a, const uint b, __global const BodyMass* masses,
                         __global const uint* flags, __global const uint* restless,
                         __global const uint* group, __global uint* marks) {
    const uint ra = restless[a], rb = restless[b];
    if (!(islandBody(masses, a) || ra) || !(islandBody(masses, b) || rb)) return;
    if (ra && (flags[b] & RUBBLE_BODY_ASLEEP)) markIslandWake(group, marks, b);
    if (rb && (flags[a] & RUBBLE_BODY_ASLEEP)) markIslandWake(group, marks, a);
}

// The islands' state from the flags, at their first use (the CPU's prepareState): no slow time,
// no group; a body asleep now sleeps alone.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
prepareIslands(const uint count, __global const uint* flags, __global float* slowFor,
               __global uint* group, __global uint* wasAsleep) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    slowFor[i] = 0.0f;
    group[i] = RUBBLE_NO_ISLAND;
    wasAsleep[i] = (flags[i] & RUBBLE_BODY_ASLEEP) ? 1u : 0u;
}

// Wake, pass 1 of a collision round (after the summaries, `marks` zero): each body's restless
// word on the velocities before the forces (restlessBeforeSolveItem); a body woken from outside
// marks its group.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
markIslandWakeBodies(const uint count, const uint capacity, __global const uint* pairCount,
                     __global const uint* flags, __global const BodyMass* masses,
                     __global const BodyVelocity* approach, __global const float* radii,
                     __global const uint* wasAsleep, __global const uint* group,
                     __global uint* restless, __global uint* marks) {
    const uint i = get_global_id(0);
    if (i >= count || pairsOverflow(capacity, pairCount)) return;
    const uint r = restlessBeforeSolveItem(flags[i], islandBody(masses, i), wasAsleep[i],
                                           approach[i], radii[i]);
    restless[i] = r;
    if (r && wasAsleep[i] && group[i] != RUBBLE_NO_ISLAND)
        atomic_or(&marks[group[i]], RUBBLE_ISLAND_WAKE_GROUP);
}

// Wake, pass 2: each pair with rows (the host's plan's pairs, summaries & RUBBLE_PGS_POINTS), and
// with `kinematicTouches` each pair with points between a moving kinematic body and a sleeping one
// (it has no rows until its sleeping body wakes), touches.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
markIslandWakePairs(const uint capacity, __global const uint* pairCount,
                    __global const BodyPairRecord* pairs, __global const uint* summaries,
                    __global const ContactManifold* manifolds, const uint kinematicTouches,
                    __global const uint* flags, __global const BodyMass* masses,
                    __global const uint* restless, __global const uint* group,
                    __global uint* marks) {
    if (pairsOverflow(capacity, pairCount)) return;
    const ItemRange r = itemRange(pairCount[0]);
    const uint moving = RUBBLE_BODY_KINEMATIC | RUBBLE_BODY_WAKING;
    for (uint p = r.first; p < r.end; p += r.step) {
        const BodyPairRecord pair = pairs[p];
        int touching = (summaries[p] & RUBBLE_PGS_POINTS) != 0u;
        if (!touching && kinematicTouches && manifolds[p].count > 0u) {
            const uint fa = flags[pair.a], fb = flags[pair.b];
            touching = ((fa & moving) == moving && (fb & RUBBLE_BODY_ASLEEP)) ||
                       ((fb & moving) == moving && (fa & RUBBLE_BODY_ASLEEP));
        }
        if (touching) touchIslands(pair.a, pair.b, masses, flags, restless, group, marks);
    }
}

// Wake, pass 2 for the joints: each joint touches as a contact does.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
markIslandWakeJoints(const uint count, __global const PgsJoint* joints, const uint capacity,
                     __global const uint* pairCount, __global const uint* flags,
                     __global const BodyMass* masses, __global const uint* restless,
                     __global const uint* group, __global uint* marks) {
    const uint j = get_global_id(0);
    if (j >= count || pairsOverflow(capacity, pairCount)) return;
    touchIslands(joints[j].a, joints[j].b, masses, flags, restless, group, marks);
}

// Wake, pass 3: the marked sleeping bodies wake, alone or with their group, keeping the zero
// velocities they slept with and their group (the step's updateSleep sees them as woken from
// outside); the woken are counted in the status block, from which the host collides again.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
wakeIslandBodies(const uint count, const uint capacity, __global const uint* pairCount,
                 __global const BodyMass* masses, __global const uint* group,
                 __global const uint* marks, __global uint* flags, __global uint* status) {
    __local uint woken[1];
    const uint i = get_global_id(0);
    const int overflow = pairsOverflow(capacity, pairCount);
    groupClear(woken, 1u);
    if (!overflow && i < count && islandBody(masses, i) && (flags[i] & RUBBLE_BODY_ASLEEP)) {
        const uint g = group[i];
        const int wakes = (marks[i] & RUBBLE_ISLAND_WAKE_BODY) ||
                          (g != RUBBLE_NO_ISLAND && (marks[g] & RUBBLE_ISLAND_WAKE_GROUP));
        if (wakes) {
            flags[i] &= ~RUBBLE_BODY_ASLEEP;
            atomic_inc(&woken[0]);
        }
    }
    if (groupDone() && woken[0] > 0u) atomic_add(&status[RUBBLE_STATUS_WOKEN], woken[0]);
}

// Sleep, pass 1, once the step has run: each dynamic awake body's slow time and restless word
// on its velocity after the step (islandBodyItem); each body its own island, each root's words
// cleared; a body of a group gives the group its index (`groupFirst`, all ones before: the
// smallest member is the one the CPU unites the others with).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
measureIslandBodies(const uint count, __global const uint* flags, __global const BodyMass* masses,
                    __global const BodyVelocity* velocities, __global const float* radii,
                    __global const uint* wasAsleep, __global const uint* group,
                    __global float* slowFor, __global uint* restless, __global uint* labels,
                    __global uint* groupFirst, __global uint* island,
                    __global uint* islandSlowFor, const float dt) {
    const uint i = get_global_id(0);
    if (i >= count) return;
    labels[i] = i;
    island[i] = 0u;
    islandSlowFor[i] = as_uint(INFINITY);
    if (group[i] != RUBBLE_NO_ISLAND) atomic_min(&groupFirst[group[i]], i);
    uint r = 0u;
    if (islandBody(masses, i) && !(flags[i] & RUBBLE_BODY_ASLEEP)) {
        const IslandBody b = islandBodyItem(slowFor[i], wasAsleep[i], velocities[i], radii[i], dt);
        slowFor[i] = b.slowFor;
        r = b.restless;
    }
    restless[i] = r;
}

// Sleep, pass 2 for the groups, before the pairs and joints: the bodies that fell asleep together
// (asleep, or woken from outside since) stay one island, each linked to its group's smallest
// member, as the CPU unites each with the first. A body writes only its own link.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
hookIslandGroups(const uint count, __global const uint* group, __global const uint* groupFirst,
                 __global uint* labels) {
    const uint i = get_global_id(0);
    if (i >= count || group[i] == RUBBLE_NO_ISLAND) return;
    labels[i] = groupFirst[group[i]];
}

// Sleep, pass 2: each pair with rows joins its dynamic bodies' islands; a dynamic awake body that
// a moving kinematic body touches is carried or pushed: restless, its slow time starting again.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_PAIRS, 1, 1))) void
uniteIslandPairs(const uint capacity, __global const uint* pairCount,
                 __global const BodyPairRecord* pairs, __global const uint* summaries,
                 __global const uint* flags, __global const BodyMass* masses,
                 __global const BodyVelocity* velocities, __global float* slowFor,
                 __global uint* restless, __global uint* labels) {
    const ItemRange r = itemRange(min(pairCount[0], capacity));
    for (uint p = r.first; p < r.end; p += r.step) {
        if ((summaries[p] & RUBBLE_PGS_POINTS) == 0u) continue;
        const BodyPairRecord pair = pairs[p];
        const int dynamicA = islandBody(masses, pair.a), dynamicB = islandBody(masses, pair.b);
        const uint fa = flags[pair.a], fb = flags[pair.b];
        if (dynamicA && !(fa & RUBBLE_BODY_ASLEEP) && movingKinematicItem(fb, velocities[pair.b])) {
            atomic_or(&restless[pair.a], 1u);
            atomic_xchg(&slowFor[pair.a], 0.0f);
        }
        if (dynamicB && !(fb & RUBBLE_BODY_ASLEEP) && movingKinematicItem(fa, velocities[pair.a])) {
            atomic_or(&restless[pair.b], 1u);
            atomic_xchg(&slowFor[pair.b], 0.0f);
        }
        if (dynamicA && dynamicB) uniteNodes(labels, pair.a, pair.b);
    }
}

// Sleep, pass 2 for the joints: each joint joins its dynamic bodies' islands.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
uniteIslandJoints(const uint count, __global const PgsJoint* joints,
                  __global const BodyMass* masses, __global uint* labels) {
    const uint j = get_global_id(0);
    if (j >= count) return;
    const uint a = joints[j].a, b = joints[j].b;
    if (islandBody(masses, a) && islandBody(masses, b)) uniteNodes(labels, a, b);
}

// Sleep, pass 3: each dynamic body's island root (no link changes now); an awake body tells its
// root that the island has an awake body, whether it is restless, and its slow time (the
// island's is the shortest: an atomic minimum on the bits, as slow times are not negative).
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
gatherIslands(const uint count, __global const uint* flags, __global const BodyMass* masses,
              __global const float* slowFor, __global const uint* restless,
              __global const uint* labels, __global uint* roots, __global uint* island,
              __global uint* islandSlowFor) {
    const uint i = get_global_id(0);
    if (i >= count || !islandBody(masses, i)) return;
    uint root = i, up = labels[i];
    while (up != root) {
        root = up;
        up = labels[root];
    }
    roots[i] = root;
    if (flags[i] & RUBBLE_BODY_ASLEEP) return;
    atomic_or(&island[root], RUBBLE_ISLAND_AWAKE | (restless[i] ? RUBBLE_ISLAND_RESTLESS : 0u));
    atomic_min(&islandSlowFor[root], as_uint(slowFor[i]));
}

// Sleep, pass 4: an island with an awake body sleeps whole once that body and every other awake
// one has been slow for RUBBLE_ISLAND_SLEEP_TIME (velocities and momenta zero, the root its
// group); else its sleeping bodies wake if one of its awake bodies is restless. A slow body
// touching a sleeping one leaves it asleep. Counts of the bodies asleep, woken and put to sleep
// go to the status block.
__kernel __attribute__((reqd_work_group_size(RUBBLE_GROUP_BODIES, 1, 1))) void
sleepIslands(const uint count, __global uint* status, __global const BodyMass* masses,
             __global const uint* roots, __global const uint* island,
             __global const uint* islandSlowFor, __global uint* flags,
             __global BodyVelocity* velocities, __global BodyMomentum* momenta,
             __global float* slowFor, __global uint* group, __global uint* wasAsleep) {
    __local uint totals[3]; // the group's bodies asleep, woken, put to sleep
    const uint i = get_global_id(0);
    groupClear(totals, 3u);
    if (i < count && islandBody(masses, i)) {
        const uint root = roots[i], words = island[root];
        uint f = flags[i];
        const int asleep = (f & RUBBLE_BODY_ASLEEP) != 0u;
        uint g = group[i];
        if (words & RUBBLE_ISLAND_AWAKE) {
            if (as_float(islandSlowFor[root]) >= RUBBLE_ISLAND_SLEEP_TIME) {
                if (!asleep) atomic_inc(&totals[2]);
                f |= RUBBLE_BODY_ASLEEP;
                g = root;
                const float4 zero = vec4(0.0f, 0.0f, 0.0f);
                velocities[i].linear = zero;
                velocities[i].angular = zero;
                momenta[i].linear = zero;
                momenta[i].angular = zero;
            } else if (asleep && (words & RUBBLE_ISLAND_RESTLESS)) {
                atomic_inc(&totals[1]);
                f &= ~RUBBLE_BODY_ASLEEP;
                slowFor[i] = 0.0f;
            }
        }
        const uint nowAsleep = (f & RUBBLE_BODY_ASLEEP) ? 1u : 0u;
        if (nowAsleep) atomic_inc(&totals[0]);
        flags[i] = f;
        group[i] = nowAsleep ? g : RUBBLE_NO_ISLAND;
        wasAsleep[i] = nowAsleep;
    }
    if (!groupDone()) return;
    if (totals[0] > 0u) atomic_add(&status[RUBBLE_STATUS_ASLEEP], totals[0]);
    if (totals[1] > 0u) atomic_add(&status[RUBBLE_STATUS_WOKEN], totals[1]);
    if (totals[2] > 0u) atomic_add(&status[RUBBLE_STATUS_FELL_ASLEEP], totals[2]);
}
