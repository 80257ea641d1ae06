// include/rubble/shared/constants.h: device constants shared by the kernels and their dispatch:
// work-group sizes and fixed limits, with units where they have one.
#pragma once

// Work-group sizes of each kind of work-item (the global size is rounded up to these).
#define RUBBLE_GROUP_BODIES 64u    // integrateVelocities, integratePositions, gathers
#define RUBBLE_GROUP_PARTICLES 64u // transformParticles, buildGrid, collideParticles
#define RUBBLE_GROUP_CONTACTS 64u  // contact rows of the Jacobi solver
#define RUBBLE_GROUP_SCAN 64u      // the serial chunks of the radix sort

// Radix sort: 4-bit digits.
#define RUBBLE_SORT_DIGIT_BITS 4u
#define RUBBLE_SORT_BUCKETS 16u

// Work sizes chosen per device, tuning parameters of host/gpu/tuning.h: the host derives them
// from the device's limits and passes them to the program as build options (-D), and dispatches
// with the same values; these defaults only let a header compile alone.
// Work-items of a radix sort pass (and of the broad phase's bounds), each owning a chunk.
#ifndef RUBBLE_SORT_ITEMS
#define RUBBLE_SORT_ITEMS 256u
#endif
// Work-group size of the SAT broad phase's per-body and per-entry kernels.
#ifndef RUBBLE_GROUP_BROAD
#define RUBBLE_GROUP_BROAD 64u
#endif
// Work-group size of the SAT narrow phase and the pair kernels.
#ifndef RUBBLE_GROUP_PAIRS
#define RUBBLE_GROUP_PAIRS 64u
#endif

// An empty cell of the particle grid (cellStart / cellEnd).
#define RUBBLE_EMPTY_CELL 0xffffffffu
// "No body" in a contact row's body b (the static world: planes, static boxes).
#define RUBBLE_NO_BODY 0xffffffffu
// "No group": a body that no joint ties to another dynamic body (sleeping by joint group).
#define RUBBLE_NO_GROUP 0xffffffffu

// A particle meets at most this many static shapes (planes and static boxes) per step.
#define RUBBLE_MAX_STATIC_SHAPES 64u

// Slots of the per-step status buffer that the host reads once at the end of a step. The
// stages after collideParticles read the contact count from it (the host does not know it when
// it enqueues them), and do nothing when it exceeds the capacity: the host then grows the
// buffer and runs them again.
#define RUBBLE_STATUS_CONTACTS 0u    // contacts appended by collideParticles (may exceed capacity)
#define RUBBLE_STATUS_NONFINITE 1u   // lowest index of a body whose state is not finite
#define RUBBLE_STATUS_PENETRATION 2u // largest contact depth, float bits (depths are >= 0)
#define RUBBLE_STATUS_RESIDUAL 3u    // largest |impulse change| in the last sweep, float bits
#define RUBBLE_STATUS_CAPACITY 4u    // room in the contact buffer, written with the reset
#define RUBBLE_STATUS_ASLEEP 5u      // bodies asleep after the step
#define RUBBLE_STATUS_WOKEN 6u       // bodies woken in the step
#define RUBBLE_STATUS_PUSHED 7u      // PGS: some row pushes (the split position pass runs)
#define RUBBLE_STATUS_PAIRS 8u        // SAT: body pairs found by the broad phase (may exceed room)
#define RUBBLE_STATUS_GRID_ENTRIES 9u // SAT: (cell, body) entries of the broad phase's grid
#define RUBBLE_STATUS_LARGE 10u       // SAT: bodies too large for the grid, tested against all
#define RUBBLE_STATUS_BOUNCES 11u     // PGS: some row may bounce (the restitution pass runs)
#define RUBBLE_STATUS_LAYERS 12u      // PGS: moving bodies 10 times apart in mass touch (layers)
#define RUBBLE_STATUS_KEPT 13u        // SAT: last step's kept pair entries (markStillPairs)
#define RUBBLE_STATUS_CARRIED 14u     // SAT: still pairs carried into the next step's set
#define RUBBLE_STATUS_FELL_ASLEEP 15u // SAT islands: bodies put to sleep at the end of the step
// PGS: PgsImpulse slots taken in the pair set being filled this step (summarizePairs, then
// carryStillPairs; may exceed the set's room)
#define RUBBLE_STATUS_IMPULSES 16u
// The dynamic bodies' mechanical energy after the step (sumBodyEnergy), J, float bits, and the
// sum of its terms' magnitudes, J, float bits: the scale of its rounding (the blow-up watch)
#define RUBBLE_STATUS_ENERGY 17u
#define RUBBLE_STATUS_ENERGY_SCALE 18u
#define RUBBLE_STATUS_COUNT 19u

// Stages over contacts run a fixed number of work-items that stride through however many
// contacts there are: this many work-groups per compute unit.
#define RUBBLE_STRIDE_GROUPS_PER_UNIT 32u

// Contacts whose bodies approach slower than this (m/s, the relative normal velocity before the
// step's forces) do not bounce, whatever their restitution: resting and slowly settling contacts
// stay put. One value for the CPU rows (host/dynamics/contact_rows.cpp) and the kernels' rows
// (rubble/shared/contact_row.h).
#define RUBBLE_RESTITUTION_THRESHOLD 0.5f

// Sleeping on the device (shared/sleep.h): a body slower than both speeds for
// RUBBLE_SLEEP_TIME, none of whose neighbours is faster, falls asleep; a body faster than
// RUBBLE_WAKE_SPEED wakes the sleeping bodies it touches.
#define RUBBLE_SLEEP_LINEAR_SPEED 0.05f  // m/s
#define RUBBLE_SLEEP_ANGULAR_SPEED 0.05f // rad/s
#define RUBBLE_SLEEP_TIME 0.5f           // s
#define RUBBLE_WAKE_SPEED 0.2f           // m/s, at the body's centre of mass
