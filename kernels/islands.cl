// kernels/islands.cl: entry points of SAT's sleep by islands on the device: the CPU's wakeIslands
// after each collision round's summaries and its updateSleep at the end of the step, the islands
// found by a concurrent union-find over the pairs with rows, the joints and the groups bodies fell
// asleep with. The math is in rubble/shared/sleep.h; the dispatch is DeviceIslands
// (host/gpu/sleep.cpp); the CPU twin host/dynamics/islands.cpp.
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/group.h"
#include "rubble/shared/narrow_phase.h"
#include "rubble/shared/pgs_joint.h"
#include "rubble/shared/pgs_row.h"
#include "rubble/shared/sleep.h"

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
