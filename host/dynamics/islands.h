// host/dynamics/islands.h: islands (union-find over touching contacts and joints) and sleeping,
// the last stage of the CPU step.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/collision/contact.h"
#include "host/core/union_find.h"
#include "rubble/shared/body.h"

namespace rubble {

/// A body is slow while no point of it moves faster than this: |v| + r |omega| < kSleepSpeed,
/// r its bounding radius (m/s). An island sleeps once all its bodies have been slow for
/// kTimeToSleep.
inline constexpr float kSleepSpeed = 0.05f; ///< m/s
inline constexpr float kTimeToSleep = 0.5f; ///< s

/// What sleeping keeps between steps, by body index.
struct SleepState {
    std::vector<float> slowFor;          ///< how long the body has been slow, s
    std::vector<std::uint32_t> group;    ///< the island it fell asleep with (kNoGroup if awake)
    std::vector<std::uint8_t> wasAsleep; ///< asleep at the end of the last step
    // Scratch reused every step.
    UnionFind islands; ///< this step's islands, over the bodies
    std::vector<std::uint32_t> groupFirst, awake, asleep, islandRestless;
    std::vector<std::uint8_t> restless, wakeGroup, wakeBody;
    std::vector<float> islandSlowFor;
    std::vector<BodyPair> touching; ///< the manifold overloads' body pairs
};

inline constexpr std::uint32_t kNoGroup = 0xffffffffu;

/// What the last update did.
struct SleepReport {
    std::uint32_t islands = 0;      ///< islands with at least one dynamic body
    std::uint32_t asleepBodies = 0; ///< bodies asleep after the update
    std::uint32_t woken = 0;        ///< bodies woken by it
    std::uint32_t fellAsleep = 0;   ///< bodies put to sleep by it
};

/// Stage wake of the reference pipeline, before the rows (as Box2D v3 wakes a sleeping island when
/// a contact with it begins, before that step's solve). A sleeping body wakes, with the bodies it
/// fell asleep with, when a manifold with points or a joint joins it to a restless awake body, or
/// when it is one of those bodies and was woken from outside this step (the API, an explosion): so
/// its mass takes part in this step's solve instead of meeting the hit as a wall. Restless here is
/// measured on `approach`, the velocities before this step's forces (the last step's velocities and
/// any impulse since), so that the step's gravity does not count as motion. A woken body keeps its
/// zero velocities and takes none of this step's forces. The woken bodies' pairs were not
/// collided while they slept: the caller collides again and calls wake again until it returns 0.
/// `joined` holds the joints' body pairs. Returns the number of bodies it woke.
/// reads: manifolds, joined, approach, radii, masses
/// writes: masses (flags), state
std::uint32_t wakeIslands(std::span<const Manifold> manifolds, std::span<const BodyPair> joined,
                          std::span<const float> radii, std::span<shared::BodyMass> masses,
                          std::span<const shared::BodyVelocity> approach, SleepState& state);
/// The same over `touching`, the body pairs of this step's manifolds with points (the device's
/// pairs with rows: host/gpu/sleep.cpp), in any order.
std::uint32_t wakeIslands(std::span<const BodyPair> touching, std::span<const BodyPair> joined,
                          std::span<const float> radii, std::span<shared::BodyMass> masses,
                          std::span<const shared::BodyVelocity> approach, SleepState& state);

/// Stage updateSleep (islands as in Catto, "Box2D" island management; union-find after Tarjan).
/// Dynamic bodies are joined by every manifold with points and every joint; bodies that fell
/// asleep together stay together (their pairs are not collided while they sleep). An island whose
/// awake bodies have all been slow for kTimeToSleep goes to sleep: RUBBLE_BODY_ASLEEP is set and
/// its velocities and momenta are zeroed. Otherwise its sleeping bodies wake when one of its
/// awake bodies is restless: not slow, or woken from outside this step (the API, an explosion;
/// such a body also starts its slow time again).
/// `joined` holds the joints' body pairs.
/// reads: manifolds, joined, velocities, radii (each body's bounding radius, m)
/// writes: masses (flags), velocities, momenta, state
SleepReport updateSleep(std::span<const Manifold> manifolds, std::span<const BodyPair> joined,
                        std::span<const float> radii, std::span<shared::BodyMass> masses,
                        std::span<shared::BodyVelocity> velocities,
                        std::span<shared::BodyMomentum> momenta, float dt, SleepState& state);
/// The same over `touching`, the body pairs of this step's manifolds with points, and `joined`,
/// the joints' body pairs, each in any order (the islands and every decision depend on the
/// pairs, not on their order: UnionFind's roots are the smallest members).
SleepReport updateSleep(std::span<const BodyPair> touching, std::span<const BodyPair> joined,
                        std::span<const float> radii, std::span<shared::BodyMass> masses,
                        std::span<shared::BodyVelocity> velocities,
                        std::span<shared::BodyMomentum> momenta, float dt, SleepState& state);

} // namespace rubble
