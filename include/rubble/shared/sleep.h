// include/rubble/shared/sleep.h: sleeping on the device, per element (stage sleepBodies,
// kernels/sleep.cl; CPU twin in host/dynamics/sleep.cpp). A body at rest long enough
// sleeps: it is not integrated, its particles start no collision tests and its contacts make
// no rows. A fast body touching it, an explosion or the host wakes it.
#pragma once

#include "rubble/shared/body.h"

RUBBLE_SHARED_BEGIN

// What a step's contacts say about a body (bits of its `restless` word).
#define RUBBLE_RESTLESS_NEIGHBOUR 1u // touches a body that is not slow: it may not fall asleep
#define RUBBLE_RESTLESS_WAKE 2u      // asleep, and touched by a body faster than the wake speed
// Bits from here up: the round of this step's collision (1, 2, ...) in which a hit woke the body
// before the solve (SAT on the device), 0 when none did.
#define RUBBLE_RESTLESS_WOKEN_SHIFT 8u

// Below both sleep speeds (RUBBLE_SLEEP_LINEAR_SPEED, RUBBLE_SLEEP_ANGULAR_SPEED).
RUBBLE_FN int slowBodyItem(BodyVelocity v) {
    return dot3(v.linear, v.linear) < RUBBLE_SLEEP_LINEAR_SPEED * RUBBLE_SLEEP_LINEAR_SPEED &&
           dot3(v.angular, v.angular) < RUBBLE_SLEEP_ANGULAR_SPEED * RUBBLE_SLEEP_ANGULAR_SPEED;
}

// Faster than the wake speed at its centre of mass, or a kinematic body that moves at all.
RUBBLE_FN int wakingBodyItem(BodyVelocity v, uint flags) {
    if (flags & RUBBLE_BODY_KINEMATIC) return !slowBodyItem(v);
    return dot3(v.linear, v.linear) > RUBBLE_WAKE_SPEED * RUBBLE_WAKE_SPEED;
}

// The restless bits one contact gives its body `self` from the other body's state and velocity:
// a neighbour that is not slow keeps an awake body awake; one that is fast wakes a sleeping
// body. Static and sleeping neighbours say nothing.
RUBBLE_FN uint restlessFromContactItem(uint selfFlags, uint otherFlags, BodyVelocity other) {
    if (otherFlags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP | RUBBLE_BODY_ABSENT)) return 0u;
    if (selfFlags & RUBBLE_BODY_ASLEEP)
        return wakingBodyItem(other, otherFlags) ? RUBBLE_RESTLESS_WAKE : 0u;
    return slowBodyItem(other) ? 0u : RUBBLE_RESTLESS_NEIGHBOUR;
}

// Whether a contact wakes its body `self` before this step's rows: `self` is asleep and the
// other body is awake and waking (wakingBodyItem) with `otherApproach`, its velocity before this
// step's forces (so that the step's gravity does not count as motion). Woken then, the body's
// mass takes part in the solve instead of meeting the hit as a wall.
RUBBLE_FN int wakesBeforeSolveItem(uint selfFlags, uint otherFlags, BodyVelocity otherApproach) {
    if (!(selfFlags & RUBBLE_BODY_ASLEEP)) return 0;
    if (otherFlags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP | RUBBLE_BODY_ABSENT)) return 0;
    return wakingBodyItem(otherApproach, otherFlags);
}

// Whether a body (`flags`, `restless`) was woken by a hit in a round of this step's collision
// before round `round` (its RUBBLE_RESTLESS_WOKEN_SHIFT bits) and is still awake.
RUBBLE_FN int wokenBeforeItem(uint flags, uint restless, uint round) {
    if (flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP | RUBBLE_BODY_ABSENT)) return 0;
    const uint wokenIn = restless >> RUBBLE_RESTLESS_WOKEN_SHIFT;
    return wokenIn > 0u && wokenIn < round;
}

// wakesBeforeSolveItem in round `round` of a step's collision, where a body that a hit woke in
// an earlier round wakes the sleeping bodies it touches as a waking one does: the hit reaches
// through the touching sleeping bodies, as it would through an island woken as one, instead of
// meeting the second of them as a wall. Round 0 (the particle paths) takes no such marks.
RUBBLE_FN int wakesInRoundItem(uint selfFlags, uint otherFlags, BodyVelocity otherApproach,
                               uint otherRestless, uint round) {
    if (wakesBeforeSolveItem(selfFlags, otherFlags, otherApproach)) return 1;
    return (selfFlags & RUBBLE_BODY_ASLEEP) && wokenBeforeItem(otherFlags, otherRestless, round);
}

// 8 bytes, not stored: a body's flags and how long it has been slow, s.
typedef struct SleepRecord {
    uint flags;
    float slowFor;
} SleepRecord;

// One step of a dynamic body's sleep: a sleeping body touched by a fast one wakes (slow time
// starting again); an awake body adds dt to its slow time while slow (else starts again) and
// falls asleep once that reaches RUBBLE_SLEEP_TIME with no restless neighbour. The caller
// zeroes the velocities and momenta of a body that fell asleep.
RUBBLE_FN SleepRecord sleepItem(SleepRecord s, uint restless, int slow, float dt) {
    SleepRecord r = s;
    if (s.flags & RUBBLE_BODY_ASLEEP) {
        if (restless & RUBBLE_RESTLESS_WAKE) {
            r.flags = s.flags & ~RUBBLE_BODY_ASLEEP;
            r.slowFor = 0.0f;
        }
        return r;
    }
    r.slowFor = slow ? s.slowFor + dt : 0.0f;
    if (r.slowFor >= RUBBLE_SLEEP_TIME && !(restless & RUBBLE_RESTLESS_NEIGHBOUR))
        r.flags = s.flags | RUBBLE_BODY_ASLEEP;
    return r;
}

// Islands (SAT on the device, kernels/islands.cl; the CPU's are host/dynamics/islands.cpp, whose
// kSleepSpeed and kTimeToSleep these are): a dynamic body is slow while its fastest point moves
// slower than RUBBLE_ISLAND_SLEEP_SPEED, and an island whose awake bodies have all been slow for
// RUBBLE_ISLAND_SLEEP_TIME sleeps as one.
#define RUBBLE_ISLAND_SLEEP_SPEED 0.05f // m/s
#define RUBBLE_ISLAND_SLEEP_TIME 0.5f   // s
// A body's island group: none (awake, or asleep alone); else the smallest index of the island it
// fell asleep with.
#define RUBBLE_NO_ISLAND 0xffffffffu
// A body's wake marks in a collision round (one word per body): bit 0 wakes the body itself, bit
// 1 the group whose index the word has.
#define RUBBLE_ISLAND_WAKE_BODY 1u
#define RUBBLE_ISLAND_WAKE_GROUP 2u
// An island root's word at the end of the step: an awake body is in it (bit 0), a restless one
// (bit 1).
#define RUBBLE_ISLAND_AWAKE 1u
#define RUBBLE_ISLAND_RESTLESS 2u

// The speed of the body's fastest point: its centre's speed plus the turn at `radius` (its
// bounding radius), m/s. The float arithmetic of the CPU's fastestPoint.
RUBBLE_FN float fastestPointItem(BodyVelocity v, float radius) {
    return length3(v.linear) + radius * length3(v.angular);
}

// A kinematic body that moves at all: it never sleeps, and wakes and keeps awake what it touches.
RUBBLE_FN int movingKinematicItem(uint flags, BodyVelocity v) {
    return (flags & RUBBLE_BODY_KINEMATIC) && fastestPointItem(v, 1.0f) > 0.0f;
}

// Restless before the solve (the CPU's wakeIslands): a moving kinematic body, or a dynamic awake
// one woken from outside since the last step (`wasAsleep`) or not slow on `approach`, the
// velocities before this step's forces. Such a body wakes the sleeping ones it touches.
RUBBLE_FN int restlessBeforeSolveItem(uint flags, int dynamic, uint wasAsleep,
                                      BodyVelocity approach, float radius) {
    if (movingKinematicItem(flags, approach)) return 1;
    if (!dynamic || (flags & RUBBLE_BODY_ASLEEP)) return 0;
    return wasAsleep != 0u || fastestPointItem(approach, radius) >= RUBBLE_ISLAND_SLEEP_SPEED;
}

// 8 bytes, not stored: a dynamic awake body's slow time after the step and whether it is
// restless (not slow, or woken from outside since the last step: its slow time starts again).
typedef struct IslandBody {
    float slowFor;
    uint restless;
} IslandBody;

// The CPU's updateSleep for one dynamic awake body, on its velocity after the step.
RUBBLE_FN IslandBody islandBodyItem(float slowFor, uint wasAsleep, BodyVelocity v, float radius,
                                    float dt) {
    const int slow = fastestPointItem(v, radius) < RUBBLE_ISLAND_SLEEP_SPEED;
    const float from = wasAsleep != 0u ? 0.0f : slowFor;
    IslandBody r;
    r.slowFor = slow ? from + dt : 0.0f;
    r.restless = (!slow || wasAsleep != 0u) ? 1u : 0u;
    return r;
}

RUBBLE_SHARED_END
