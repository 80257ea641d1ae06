// tests/support/device_stage.h: the device stages of a stage input built alone on one queue
// (its bodies, their particles or hulls, the pairs, the solvers), so that a device stage and
// its CPU twin run on the same arrays; and a whole pipeline of the same input.
#pragma once

#include <memory>
#include <utility>

#include "host/collision/particles.h"
#include "host/gpu/pipeline.h"
#include "support/stage_input.h"

namespace rubble::test {

/// A stage input with its particle set and the device stages over it. The stages refer to one
/// another (the particles to the pairs): a DeviceStage stays where it was made.
struct DeviceStage {
    StageInput in;
    ParticleSet particles;
    std::unique_ptr<gpu::StageQueue> queue;
    gpu::DeviceBodies bodies;
    gpu::RadixSort sort;
    gpu::ParticleCollision collision;
    gpu::PairStore pairs;
    gpu::DeviceShapes shapes;
    gpu::SatBroadPhase broad;
    gpu::DeviceJoints joints;
    gpu::PgsSolve pgs;
    gpu::JacobiSolve jacobi;

    DeviceStage() = default;
    DeviceStage(const DeviceStage&) = delete;
    DeviceStage& operator=(const DeviceStage&) = delete;

    bool sat = false; ///< made by satStage

    gpu::StageQueue& q() { return *queue; }
    const gpu::Context& context() const { return queue->c(); }
    // The stages called as the pipeline's step calls them (host/gpu/device_step.cpp).
    Status uploadBodies(BodiesView view) { return bodies.upload(q(), view); }
    Status resetStatus() {
        return q().resetStatus(sat ? 0xffffffffu : collision.contacts().capacity);
    }
    Result<gpu::DeviceStatus> readStatus() { return q().readStatus(); }
    Status finish() { return q().finish(); }
    Status computeAabbs(float dt) { return broad.computeAabbs(q(), bodies, shapes, dt); }
    Status findPairs() { return broad.findPairs(q(), bodies, pairs, sort); }
    Status broadPhase(float dt) { return broad.run(q(), bodies, shapes, pairs, sort, dt); }
    /// Waits for the pair count; past the capacity the pair buffers grow and findPairs runs
    /// again. Returns the count.
    Result<std::uint32_t> readPairCount() {
        for (;;) {
            Result<gpu::DeviceStatus> st = q().readStatus();
            RUBBLE_TRY(st);
            if (st->pairs <= pairs.current.capacity) return st->pairs;
            RUBBLE_TRY(pairs.setCapacity(q(), st->pairs + st->pairs / 2));
            RUBBLE_TRY(findPairs());
        }
    }
    Status narrowPhase(float dt) {
        return gpu::collideShapes(q(), bodies, shapes, broad.spin(), broad.boxes(), pairs, dt);
    }
    Status uploadPairs(std::span<const BodyPair> list) {
        return pairs.upload(q(), list, bodies.count);
    }
    Result<std::vector<BodyPair>> downloadPairs() {
        Result<gpu::DeviceStatus> st = q().readStatus();
        RUBBLE_TRY(st);
        return pairs.downloadPairs(q(), st->pairs);
    }
    Result<std::vector<shared::ContactManifold>> downloadManifolds() {
        Result<gpu::DeviceStatus> st = q().readStatus();
        RUBBLE_TRY(st);
        return pairs.downloadManifolds(q(), st->pairs);
    }
    Result<std::vector<shared::PairCache>> downloadPairFeatures() {
        Result<gpu::DeviceStatus> st = q().readStatus();
        RUBBLE_TRY(st);
        return pairs.downloadFeatures(q(), st->pairs);
    }
    Result<std::vector<shared::BodyBox>> downloadBoxes() {
        return broad.downloadBoxes(q(), bodies.count);
    }
    Status keepPairFeatures() { return pairs.keep(q(), bodies, sat); }
    Status summarizePairs(const StepParams& params) {
        return pgs.summarize(q(), bodies, pairs, joints, params);
    }
    Status colorPgs() { return pgs.plan(q(), pairs, joints, bodies, q().lastStatus()); }
    Status buildPgsRows(const StepParams& params) {
        return pgs.buildRows(q(), bodies, pairs, params);
    }

    /// Device time of each kernel and transfer so far; collect() adds the commands enqueued
    /// since the last call (all must have completed).
    std::vector<gpu::CommandTotals> profileTotals() const { return queue->profile().totals(); }
    Result<gpu::DeviceTimes> collectProfile(const gpu::TrafficCounts& counts) {
        return q().profile().collect(counts);
    }

    /// Reads `n` elements of a device buffer.
    template <class T> std::vector<T> read(const gpu::Buffer& b, std::size_t n) {
        std::vector<T> v(n);
        const Status s = gpu::download(context(), b, std::span(v));
        if (!s.ok()) abortOn(s.error());
        return v;
    }
};

/// The input's bodies on a new queue of `context` with the stages of the particle method:
/// its shapes voxelised at the scene's particle spacing (for the scene's solver: PGS has a
/// contact margin, a scattered particle order, and pairs of one point). Errors: those of
/// buildParticleSet and the stages' creation.
inline Result<std::unique_ptr<DeviceStage>> deviceStage(std::shared_ptr<gpu::Context> context,
                                                        StageInput in) {
    auto d = std::make_unique<DeviceStage>();
    d->in = std::move(in);
    const bool pgs = d->in.scene.simulation.solverType() == SolverType::Pgs;
    Result<ParticleSet> set =
        buildParticleSet(d->in.shapes, d->in.scene.materials, d->in.bodies.view(),
                         d->in.scene.simulation.collision.particleSpacing, pgs);
    RUBBLE_TRY(set);
    d->particles = std::move(*set);
    Result<std::unique_ptr<gpu::StageQueue>> q = gpu::StageQueue::create(std::move(context));
    RUBBLE_TRY(q);
    d->queue = std::move(*q);
    const BodiesView view = d->in.bodies.view();
    RUBBLE_TRY(d->bodies.create(d->q(), view, d->in.surfaces, {}));
    RUBBLE_TRY(d->sort.create(d->q()));
    RUBBLE_TRY(d->collision.create(d->q(), &d->particles, view, pgs ? &d->pairs : nullptr));
    if (pgs) {
        RUBBLE_TRY(d->pgs.create(d->q(), d->bodies.count, 0));
        RUBBLE_TRY(d->joints.create(d->q(), {}, view, d->bodies.kinematic));
    }
    RUBBLE_TRY(d->q().finish());
    return d;
}

/// The input's bodies on a new queue of `context` with the stages of the SAT method (hulls,
/// boxes, pairs, manifolds; no particles), its PGS in `pgsBlocks` blocks (RunOptions::pgsBlocks:
/// -1 as the device suits), colored by the device when `deviceColoring` and there are no
/// blocks. Errors: those of the stages' creation.
inline Result<std::unique_ptr<DeviceStage>> satStage(std::shared_ptr<gpu::Context> context,
                                                     StageInput in, int pgsBlocks = -1,
                                                     bool deviceColoring = false) {
    auto d = std::make_unique<DeviceStage>();
    d->in = std::move(in);
    d->sat = true;
    Result<std::unique_ptr<gpu::StageQueue>> q = gpu::StageQueue::create(std::move(context));
    RUBBLE_TRY(q);
    d->queue = std::move(*q);
    gpu::StageQueue& sq = d->q();
    const BodiesView view = d->in.bodies.view();
    const auto n = std::uint32_t(view.count());
    RUBBLE_TRY(d->bodies.create(sq, view, d->in.surfaces, {}));
    RUBBLE_TRY(d->sort.create(sq));
    RUBBLE_TRY(d->shapes.create(sq, d->in.shapes, view.shapeOf));
    RUBBLE_TRY(d->broad.create(sq, view, d->in.shapes, d->in.joined));
    RUBBLE_TRY(d->pairs.create(sq, std::max<std::uint32_t>(1024, 4 * n), false));
    const std::uint32_t blocks = pgsBlocks >= 0
                                     ? std::uint32_t(pgsBlocks)
                                     : gpu::defaultPgsBlocks(sq.c().workSizes().pgsBlocks, n,
                                                             sq.c().workSizes().pgsBlockBodies);
    RUBBLE_TRY(d->pgs.create(sq, n, blocks, deviceColoring));
    RUBBLE_TRY(d->joints.create(sq, {}, view, d->bodies.kinematic));
    RUBBLE_TRY(sq.finish());
    return d;
}

/// A whole pipeline of the input's bodies (the particle method unless `collision` says SAT;
/// `contactCapacity` 0: the pipeline's own first guess), deterministic (contacts sorted, so
/// that two runs give the same bits). Errors: those of Pipeline::create.
inline Result<gpu::PipelineHandle> pipelineOf(std::shared_ptr<gpu::Context> context,
                                              const StageInput& in, const ParticleSet* particles,
                                              CollisionMethod collision,
                                              std::uint32_t contactCapacity = 0) {
    gpu::PipelineInput input;
    input.bodies = in.bodies.view();
    input.particles = particles;
    input.surfaces = in.surfaces;
    input.deterministic = true;
    input.collision = collision;
    input.shapes = in.shapes;
    input.joined = in.joined;
    input.particlePgs = in.scene.simulation.solverType() == SolverType::Pgs;
    input.contactCapacity = contactCapacity;
    return gpu::Pipeline::create(std::move(context), input);
}

} // namespace rubble::test
