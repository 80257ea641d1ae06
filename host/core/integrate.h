// host/core/integrate.h: CPU stages 2 and 7 (and OpenCL stages 1 and 6's twins): momenta from
// forces, velocities derived from momenta, positions from velocities. Per-element math is in
// rubble/shared/body.h.
#pragma once

#include <span>

#include "rubble/shared/body.h"

namespace rubble {

/// Stage integrateVelocities: P += dt (F + m g), L += dt tau, then v = P/m, omega = I_w^-1 L.
/// A kinematic body's velocities stay as they are (and are its `beforeForces`).
/// Every body's velocities before the forces go to `beforeForces` (beforeForcesItem): the
/// approach speeds of restitution, and the velocities explicit Euler moves positions with.
/// reads: momenta, forces, masses, poses, velocities   writes: momenta, velocities, beforeForces
void integrateVelocities(std::span<shared::BodyMomentum> momenta,
                         std::span<const shared::BodyForce> forces,
                         std::span<const shared::BodyMass> masses,
                         std::span<const shared::BodyPose> poses,
                         std::span<shared::BodyVelocity> velocities,
                         std::span<shared::BodyVelocity> beforeForces, shared::float4 gravity,
                         float dt);

/// Momenta take up the change that constraint impulses made to the velocities.
/// reads: before, after, masses, poses   writes: momenta
void absorbVelocityChange(std::span<shared::BodyMomentum> momenta,
                          std::span<const shared::BodyVelocity> before,
                          std::span<const shared::BodyVelocity> after,
                          std::span<const shared::BodyMass> masses,
                          std::span<const shared::BodyPose> poses);

/// Stage integratePositions. Symplectic Euler: x += dt v with the new velocities, the orientation
/// turned by the new momentum's angular velocity at the half-step orientation. Explicit Euler:
/// x += dt v0, q += dt/2 (omega0, 0) q with the start-of-step velocities `atStart`. Quaternions are
/// renormalised; velocities are then derived again from the momenta at the new orientation.
/// A kinematic body moves by its velocities (explicit Euler), which stay as they are.
/// reads: velocities (or atStart), momenta, masses   writes: poses, velocities
void integratePositions(std::span<shared::BodyPose> poses,
                        std::span<shared::BodyVelocity> velocities,
                        std::span<const shared::BodyVelocity> atStart,
                        std::span<const shared::BodyMomentum> momenta,
                        std::span<const shared::BodyMass> masses, float dt, bool symplectic);

} // namespace rubble
