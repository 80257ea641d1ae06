// host/gpu/pipeline.cpp: the device arrays of a world, their transfers, and the device step as
// a list of stages, each timed (the stage waits for the queue so that its time is its own).
#include "host/gpu/pipeline.h"

#include <chrono>
#include <cstring>

#include "host/core/math.h"
#include "host/world/world_state.h"

namespace rubble::gpu {

void PipelineDeleter::operator()(Pipeline* p) const { delete p; }

namespace {

// Adds the wall time of its scope to a StepStats field, in milliseconds.
class StageTimer {
  public:
    explicit StageTimer(double& total) : total_(total), start_(Clock::now()) {}
    ~StageTimer() {
        total_ += std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
    }
    StageTimer(const StageTimer&) = delete;
    StageTimer& operator=(const StageTimer&) = delete;

  private:
    using Clock = std::chrono::steady_clock;
    double& total_;
    Clock::time_point start_;
};

template <class T> std::span<const T> view(const std::vector<T>& v) { return {v.data(), v.size()}; }

} // namespace

Result<PipelineHandle> Pipeline::create(std::shared_ptr<Context> context, const WorldState& s) {
    PipelineHandle p(new Pipeline(std::move(context)));
    const Context& c = *p->context_;
    const std::size_t n = s.bodyCount();
    p->bodies_.count = std::uint32_t(n);
    RUBBLE_TRY(p->bodies_.atStart.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(p->bodies_.before.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(upload(c, p->bodies_.forces, view(s.forces)));
    RUBBLE_TRY(p->status_.reserve(c.context(), RUBBLE_STATUS_COUNT * sizeof(cl_uint)));
    RUBBLE_TRY(p->uploadBodies(s));
    RUBBLE_TRY(p->uploadParticles(s));
    return p;
}

Status Pipeline::uploadBodies(const WorldState& s) {
    const Context& c = *context_;
    RUBBLE_TRY(upload(c, bodies_.poses, view(s.poses)));
    RUBBLE_TRY(upload(c, bodies_.velocities, view(s.velocities)));
    RUBBLE_TRY(upload(c, bodies_.momenta, view(s.momenta)));
    RUBBLE_TRY(upload(c, bodies_.masses, view(s.masses)));
    return {};
}

Status Pipeline::downloadBodies(WorldState& s) {
    const Context& c = *context_;
    RUBBLE_TRY(download(c, bodies_.poses, std::span(s.poses)));
    RUBBLE_TRY(download(c, bodies_.velocities, std::span(s.velocities)));
    RUBBLE_TRY(download(c, bodies_.momenta, std::span(s.momenta)));
    return {};
}

Status Pipeline::uploadForces(std::span<const shared::BodyForce> forces) {
    RUBBLE_TRY(upload(*context_, bodies_.forces, forces));
    forcesOnDevice_ = true;
    return {};
}

Status Pipeline::copyVelocities(Buffer& to) {
    const std::size_t bytes = std::size_t(bodies_.count) * sizeof(shared::BodyVelocity);
    if (bytes == 0) return {};
    RUBBLE_CL_CHECK(clEnqueueCopyBuffer(context_->queue(), bodies_.velocities.mem(), to.mem(), 0,
                                        0, bytes, 0, nullptr, nullptr));
    return {};
}

Status Pipeline::resetStatus() {
    const cl_uint initial[RUBBLE_STATUS_COUNT] = {0u, 0xffffffffu, 0u, 0u};
    RUBBLE_CL_CHECK(clEnqueueWriteBuffer(context_->queue(), status_.mem(), CL_TRUE, 0,
                                         sizeof initial, initial, 0, nullptr, nullptr));
    return {};
}

Result<DeviceStatus> Pipeline::readStatus() {
    cl_uint slots[RUBBLE_STATUS_COUNT] = {};
    RUBBLE_CL_CHECK(clEnqueueReadBuffer(context_->queue(), status_.mem(), CL_TRUE, 0, sizeof slots,
                                        slots, 0, nullptr, nullptr));
    DeviceStatus d;
    d.contacts = slots[RUBBLE_STATUS_CONTACTS];
    d.firstNonFinite = slots[RUBBLE_STATUS_NONFINITE];
    std::memcpy(&d.largestPenetration, &slots[RUBBLE_STATUS_PENETRATION], sizeof(float));
    std::memcpy(&d.solverResidual, &slots[RUBBLE_STATUS_RESIDUAL], sizeof(float));
    return d;
}

Status Pipeline::finish() {
    RUBBLE_CL_CHECK(clFinish(context_->queue()));
    return {};
}

Status Pipeline::step(WorldState& s, StepStats& stats) {
    const float dt = s.options.dt;
    const bool symplectic = s.options.integrator == Integrator::Symplectic;
    RUBBLE_TRY(resetStatus());
    {
        StageTimer t(stats.integrateVelocitiesMs);
        // Explicit Euler moves positions with the velocities the step started with.
        if (!symplectic) RUBBLE_TRY(copyVelocities(bodies_.atStart));
        RUBBLE_TRY(integrateVelocities(toFloat4(s.options.gravity), dt));
        RUBBLE_TRY(finish());
    }
    {
        StageTimer t(stats.broadPhaseMs);
        RUBBLE_TRY(transformParticles());
        RUBBLE_TRY(buildGrid());
        RUBBLE_TRY(finish());
    }
    {
        StageTimer t(stats.narrowPhaseMs);
        RUBBLE_TRY(collideParticles());
        if (s.run.deterministic) RUBBLE_TRY(sortContacts());
        RUBBLE_TRY(finish());
    }
    const SolverOptions& solver = s.options.solver;
    {
        StageTimer t(stats.buildContactRowsMs);
        RUBBLE_TRY(buildJacobiRows(solverParams(solver, dt), solver.warmStart));
        RUBBLE_TRY(finish());
    }
    {
        StageTimer t(stats.solveMs);
        // lcp-jacobi solves the dense problem; the Jacobi stage then only applies its impulses.
        const bool dense = solver.type == SolverType::LcpJacobi;
        if (dense)
            RUBBLE_TRY(solveLcpJacobi(lcpStride(bodySurfaces(s), s.masses),
                                      solver.iterations, lcpJacobiRelaxation(solver)));
        RUBBLE_TRY(solveJacobi(dense ? 0 : solver.iterations, jacobiRelaxation(solver),
                               solver.warmStart));
        RUBBLE_TRY(finish());
    }
    {
        StageTimer t(stats.integratePositionsMs);
        RUBBLE_TRY(integratePositions(dt, symplectic));
        // Forces hold for one step.
        if (forcesOnDevice_) {
            RUBBLE_TRY(fill(*context_, bodies_.forces, 0u,
                            std::size_t(bodies_.count) * sizeof(shared::BodyForce)));
            forcesOnDevice_ = false;
        }
        RUBBLE_TRY(finish());
    }
    Result<DeviceStatus> status = readStatus();
    RUBBLE_TRY(status);
    stats.contactCount = contacts_.count;
    stats.largestPenetration = status->largestPenetration;
    stats.solverResidual = status->solverResidual;
    if (status->firstNonFinite < bodies_.count)
        return makeError(ErrorKind::Numerical, "body " + s.names[status->firstNonFinite],
                         "its state is not finite after step " + std::to_string(s.step + 1) +
                             " (t = " + std::to_string(double(s.step + 1) * double(dt)) + " s)");
    return {};
}

} // namespace rubble::gpu
