// host/gpu/pipeline.cpp: a world's device stages made for its collision method and solver, and
// the transfers of its bodies. The step itself is host/gpu/device_step.cpp.
#include "host/gpu/pipeline.h"

#include <algorithm>

#include "host/core/assert.h"

namespace rubble::gpu {

void PipelineDeleter::operator()(Pipeline* p) const {
    delete p;
}

Result<PipelineHandle> Pipeline::create(std::shared_ptr<Context> context, const PipelineInput& in) {
    const BodiesView bodies = in.bodies;
    const std::size_t n = bodies.count();
    if (n >= RUBBLE_TAG_MAX_BODIES)
        return makeError(ErrorKind::NotSupported, "bodies",
                         "the OpenCL pipeline takes fewer than " +
                             std::to_string(RUBBLE_TAG_MAX_BODIES) + " bodies; this world has " +
                             std::to_string(n));
    // A buffer the device or the process had no room for (host/gpu/memory.h) says so.
    auto named = [](Error e) {
        if (e.kind == ErrorKind::Limit && e.where == "device memory")
            e.where = "device memory, creating the world's device buffers";
        return e;
    };
    PipelineHandle p(new Pipeline());
    Result<std::unique_ptr<StageQueue>> queue = StageQueue::create(std::move(context));
    if (!queue.ok()) return named(queue.error());
    p->queue_ = std::move(*queue);
    if (Status made = p->makeStages(in); !made.ok()) return named(made.error());
    return p;
}

Status Pipeline::makeStages(const PipelineInput& in) {
    const BodiesView bodies = in.bodies;
    const std::size_t n = bodies.count();
    StageQueue& q = *queue_;
    method_ = in.collision;
    deterministic_ = in.deterministic;
    particlePgs_ = in.collision == CollisionMethod::Particles && in.particlePgs;
    lcpStride_ = lcpStride(in.surfaces, bodies.masses);
    RUBBLE_TRY(bodies_.create(q, bodies, in.surfaces, in.kinematic));
    RUBBLE_TRY(sort_.create(q));
    RUBBLE_TRY(obstacles_.create(q, bodies_));
    if (sat()) {
        RUBBLE_TRY(shapes_.create(q, in.shapes, bodies.shapeOf));
        RUBBLE_TRY(broadPhase_.create(q, bodies, in.shapes, in.joined));
        // Pairs: a first guess of four per body.
        const std::uint32_t guess = in.pairCapacity > 0
                                        ? in.pairCapacity
                                        : std::max<std::uint32_t>(1024, 4 * std::uint32_t(n));
        RUBBLE_TRY(pairs_.create(q, guess, false));
        if (in.islands) {
            std::vector<float> radii(n);
            for (std::size_t i = 0; i < n; ++i)
                radii[i] = in.shapes[bodies.shapeOf[i]].boundingRadius;
            islands_ = std::make_unique<DeviceIslands>();
            RUBBLE_TRY(islands_->create(q, bodies_, radii));
        }
    }
    // Particles: their set and contact buffers, and with PGS a pair of one point per contact.
    if (!sat())
        RUBBLE_TRY(particles_.create(q, in.particles, bodies, particlePgs_ ? &pairs_ : nullptr,
                                     in.contactCapacity));
    if (pairPgs()) {
        const std::uint32_t blocks = in.pgsBlocks >= 0
                                         ? std::uint32_t(in.pgsBlocks)
                                         : defaultPgsBlocks(q.c().workSizes().pgsBlocks, n,
                                                            q.c().workSizes().pgsBlockBodies);
        RUBBLE_TRY(pgs_.create(q, std::uint32_t(n), blocks, in.pgsColoring == PgsColoring::Device));
        RUBBLE_TRY(joints_.create(q, in.joints, bodies, bodies_.kinematic));
        if (sat()) RUBBLE_TRY(softStep_.create(q, std::uint32_t(n)));
    }
    hostWrote_ = true;
    RUBBLE_TRY(q.finish());
    return {};
}

Status Pipeline::uploadBodies(BodiesView bodies) {
    RUBBLE_TRY(bodies_.upload(*queue_, bodies));
    // The host's flags are the islands' from here on (a body woken by the host wakes its
    // island; updateSleep sees it as woken from outside).
    if (islands_) islands_->reset(bodies_);
    hostWrote_ = true;
    uploaded_ = true;
    return {};
}

Status Pipeline::uploadForces(std::span<const shared::BodyForce> forces) {
    return bodies_.uploadForces(*queue_, forces);
}

std::optional<std::pair<float, float>> Pipeline::energyOfLastStep() const {
    if (!energySummed_) return std::nullopt;
    const DeviceStatus st = queue_->lastStatus();
    return std::pair(st.energy, st.energyScale);
}

Status Pipeline::downloadLowestEnergies(std::vector<double>& out) {
    Result<std::vector<float>> e = download<float>(queue_->c(), energy_.atLowest, bodies_.count);
    RUBBLE_TRY(e);
    out.assign(e->begin(), e->end());
    return {};
}

Status Pipeline::downloadBodies(Bodies bodies) {
    ++bodyReads_;
    RUBBLE_TRY(bodies_.enqueueRead(*queue_, bodies, false));
    RUBBLE_TRY(queue_->finish());
    bodies_.takeSleepFlags(bodies);
    return {};
}

Status Pipeline::downloadPoses(std::uint32_t first, std::uint32_t count, void* out) {
    RUBBLE_ASSERT(std::size_t(first) + count <= bodies_.count);
    return readBytes(queue_->c(), bodies_.poses, first * sizeof(shared::BodyPose), out,
                     count * sizeof(shared::BodyPose), Wait::Done);
}

bool Pipeline::atRest() const {
    return sat() && islands_ && !stepPending_ && pairsFound_ == 0 && keptFound_ == 0 &&
           islands_->asleep() == bodies_.moving && !hostWrote_ && !bodies_.forcesOnDevice &&
           obstacles_.count() == 0;
}

} // namespace rubble::gpu
