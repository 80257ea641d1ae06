// host/gpu/soft_step.h: the soft step on the device (kernels/soft_step.cl) over the PGS path's
// pair summaries, plan (blocks and colors) and rows (host/gpu/pgs.h): the substeps with soft
// contacts and joints, relax passes, restitution and the impulses kept. The CPU twin is
// SoftStepSolver (host/dynamics/soft_step_solver.cpp).
#pragma once

#include <cstdint>

#include "host/core/step_params.h"
#include "host/gpu/device_bodies.h"
#include "host/gpu/joints.h"
#include "host/gpu/pairs.h"
#include "host/gpu/pgs.h"

namespace rubble::gpu {

/// The soft step's settings of one step, from the solver options and dt, as the CPU's
/// makeSoftStepSettings makes them: the springs (softnessItem) of contacts between moving
/// bodies, of contacts against a body that does not move, and of joints.
struct SoftStepLaunch {
    std::uint32_t substeps = 1, relaxIterations = 0;
    float h = 0.0f, inverseH = 0.0f, maxPushSpeed = 0.0f, restitutionThreshold = 0.0f;
    shared::float4 contactSoft{}, stillSoft{}, jointSoft{};
};
SoftStepLaunch makeSoftStepLaunch(const SolverOptions& options, float dt);

class SoftStepSolve {
  public:
    /// Errors: Device.
    Status create(StageQueue& q, std::uint32_t bodies);
    /// Stage solve, after PgsSolve::buildRows (the plan and the warm-started rows): each point's
    /// soft contact; per substep the forces' share, warm start, the biased pass (joints, then
    /// contacts), the motion over h and the relax passes, one launch of each per block set and
    /// color; then restitution with the impulses kept for the next step, and the step's end:
    /// momenta, poses and velocities (the step leaves integratePositions out).
    /// reads: rows, manifolds, bodies, joints   writes: velocities, momenta, poses, impulses
    Status solve(StageQueue& q, DeviceBodies& b, const PgsSolve& pgs, PairStore& pairs,
                 DeviceJoints& joints, const StepParams& params);

  private:
    Buffer contacts_;  ///< SoftContact per point, at its rows' index
    Buffer share_;     ///< per body: a substep's share of the forces' velocity change
    Buffer softPoses_; ///< per body: the pose through the substeps
    Buffer moved_;     ///< per body: x - x at the step's start, m
};

} // namespace rubble::gpu
