// host/gpu/integrate.h: the device's integration stages (kernels/integrate.cl), each the twin
// of the CPU function of the same name (host/core/integrate.h). They only enqueue.
#pragma once

#include "host/gpu/device_bodies.h"
#include "rubble/shared/math.h"

namespace rubble::gpu {

/// Reads momenta, forces, masses, flags, poses; writes momenta, velocities and atStart (the
/// velocities before the forces).
Status integrateVelocities(StageQueue& q, DeviceBodies& b, shared::float4 gravity, float dt);
/// The solve's velocity change (velocities against `before`) into the momenta.
Status absorbVelocityChange(StageQueue& q, DeviceBodies& b);
/// Moves the poses by the velocities (symplectic) or by atStart (explicit Euler); checks
/// finiteness into the status block. `pushesFollow`: applyPushes comes next and derives the
/// velocities of the bodies that moved in the solve, so this leaves theirs.
Status integratePositions(StageQueue& q, DeviceBodies& b, float dt, bool symplectic,
                          bool pushesFollow = false);
/// The device's record of the bodies' energy for the blow-up watch: each body's this step, each
/// body's at the lowest total since the watch's reference, and that total (J).
struct EnergyBuffers {
    Buffer energies, atLowest, lowest;
};

/// The dynamic bodies' mechanical energy in `gravity` (m/s^2), summed on the device into the
/// status block (DeviceStatus::energy and its rounding scale) for the host's blow-up watch;
/// when the total is the lowest since the reference (or `restart`: this step is the new
/// reference) each body's energy is kept in e.atLowest. Errors: Device.
Status sumBodyEnergy(StageQueue& q, DeviceBodies& b, EnergyBuffers& e, shared::float4 gravity,
                     bool restart);

} // namespace rubble::gpu
