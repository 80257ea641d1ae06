// tests/support/device_stage.h: a device pipeline made from a stage input (its bodies, their
// particles, surfaces), so that a device stage and its CPU twin run on the same arrays.
#pragma once

#include <memory>
#include <utility>

#include "host/collision/particles.h"
#include "host/gpu/pipeline.h"
#include "support/stage_input.h"

namespace rubble::test {

/// A stage input with its particle set and a pipeline holding both.
struct DeviceStage {
    StageInput in;
    ParticleSet particles;
    gpu::PipelineHandle pipeline;

    gpu::Pipeline& device() { return *pipeline; }
};

/// Voxelises the input's shapes at the scene's particle spacing (for the scene's solver: PGS
/// has a contact margin and a scattered particle order) and puts the bodies on a new pipeline of
/// `context`. Errors: those of buildParticleSet and Pipeline::create.
inline Result<DeviceStage> deviceStage(std::shared_ptr<gpu::Context> context, StageInput in,
                                       bool deterministic = false) {
    DeviceStage d;
    d.in = std::move(in);
    Result<ParticleSet> set =
        buildParticleSet(d.in.shapes, d.in.scene.materials, d.in.bodies.view(),
                         d.in.scene.simulation.collision.particleSpacing,
                         d.in.scene.simulation.solverType() == SolverType::Pgs);
    RUBBLE_TRY(set);
    d.particles = std::move(*set);
    gpu::PipelineInput input;
    input.bodies = d.in.bodies.view();
    input.particles = &d.particles;
    input.surfaces = d.in.surfaces;
    input.deterministic = deterministic;
    Result<gpu::PipelineHandle> p = gpu::Pipeline::create(std::move(context), input);
    RUBBLE_TRY(p);
    d.pipeline = std::move(*p);
    return d;
}

/// The input's bodies on a new pipeline of `context` made for the SAT method (hulls, boxes,
/// pairs, manifolds; no particles), its PGS in `pgsBlocks` blocks (RunOptions::pgsBlocks).
/// Errors: those of Pipeline::create.
inline Result<gpu::PipelineHandle> satPipeline(std::shared_ptr<gpu::Context> context,
                                               const StageInput& in, int pgsBlocks = -1) {
    gpu::PipelineInput input;
    input.bodies = in.bodies.view();
    input.surfaces = in.surfaces;
    input.collision = CollisionMethod::Sat;
    input.shapes = in.shapes;
    input.joined = in.joined;
    input.pgsBlocks = pgsBlocks;
    return gpu::Pipeline::create(std::move(context), input);
}

} // namespace rubble::test
