// host/gpu/pgs.cpp: dispatch of projected Gauss-Seidel on the device: the pairs' summaries,
// the rows, warm start, velocity sweeps and the split position pass (one launch for the blocks
// and one per color), the layer pass, the restitution pass and the pushes. The plan between the
// summaries and the rows is host/gpu/pgs_plan.cpp; the CPU twin is PgsSolver
// (host/dynamics/pgs_solver.cpp).
#include "host/gpu/pgs.h"

#include <algorithm>

#include "host/core/assert.h"
#include "host/gpu/integrate.h"
#include "host/gpu/jacobi.h"

namespace rubble::gpu {
namespace {

// Bytes one launch of a sweep kernel moves for a color of `elements` elements with `points`
// rows: each element's record, both bodies' velocities read and written, and per point its
// rows (`rowBytes`) and its impulses read and written.
std::uint64_t sweepBytes(std::uint64_t elements, std::uint64_t points, std::uint64_t rowBytes) {
    constexpr std::uint64_t kVelocity = sizeof(shared::BodyVelocity);
    return elements * (sizeof(shared::PgsElement) + 4 * kVelocity) +
           points * (rowBytes + 2 * sizeof(shared::float4));
}

// The arguments summarizePairs and buildPgsRows both read, in their kernels' order: the rows'
// settings (baumgarte, slop, dt, warm start) and last step's pairs and impulses.
void bindRowSettings(Dispatch& d, const PairStore& pairs, const StepParams& params) {
    const SolverOptions& o = params.solver;
    const cl_float baumgarte = o.baumgarte, slop = o.slop, dt = params.dt;
    const cl_uint warm = o.warmStart ? 1u : 0u, previousCapacity = pairs.previous.capacity;
    d.arg(baumgarte)
        .arg(slop)
        .arg(dt)
        .arg(warm)
        .arg(previousCapacity)
        .arg(pairs.previous.count)
        .arg(pairs.previousOf)
        .arg(pairs.previous.impulseCount)
        .arg(pairs.previous.impulseStart)
        .arg(pairs.previous.impulses);
}

} // namespace

Status PgsSolve::create(StageQueue& q, std::uint32_t bodies, std::uint32_t blocks,
                        bool deviceColoring) {
    const Context& c = q.c();
    blocks_ = blocks;
    devicePlan_ = blocks == 0 && deviceColoring;
    if (devicePlan_) RUBBLE_TRY(createDevicePlan(q, bodies));
    RUBBLE_TRY(pushed_.reserve(c.context(), bodies * sizeof(cl_uint)));
    return push_.reserve(c.context(), bodies * sizeof(shared::BodyVelocity));
}

// A sweep kernel's launch (a color, the serial tail or the blocks), its first arguments bound:
// the launch's first element, count and mode, the step's elements and the blocks' starts.
Dispatch PgsSolve::launch(StageQueue& q, KernelId id, const PgsLaunch& l) const {
    Dispatch d(q.c(), id, &q.profile());
    d.arg(l.first).arg(l.count).arg(l.mode).arg(elements_).arg(devicePlan_ ? colorStarts_
                                                                           : blockStarts_);
    return d;
}

// A sweep's launch with the rows, the joints and the bodies bound after its first arguments:
// what the warm start and the velocity sweeps both read next.
Dispatch PgsSolve::rowLaunch(StageQueue& q, KernelId id, const PgsLaunch& l,
                             const DeviceJoints& joints, const DeviceBodies& b) const {
    Dispatch d = launch(q, id, l);
    d.arg(normalRows_)
        .arg(frictionRows_)
        .arg(impulses_)
        .arg(joints.joints)
        .arg(joints.rows)
        .arg(b.jacobi)
        .arg(b.velocities);
    return d;
}

Status PgsSolve::summarize(StageQueue& q, DeviceBodies& b, PairStore& pairs, DeviceJoints& joints,
                           const StepParams& params) {
    const Context& c = q.c();
    summariesRead_ = false;
    RUBBLE_TRY(prepareJacobiBodies(q, b));
    RUBBLE_TRY(fill(c, pushed_, 0u, std::size_t(b.count) * sizeof(cl_uint), &q.profile()));
    // The marks of this round of the collision (a pair overflow runs it again).
    RUBBLE_TRY(fillRange(c, q.status(), 0u, RUBBLE_STATUS_PUSHED * sizeof(cl_uint), sizeof(cl_uint),
                         &q.profile()));
    RUBBLE_TRY(fillRange(c, q.status(), 0u, RUBBLE_STATUS_BOUNCES * sizeof(cl_uint),
                         2 * sizeof(cl_uint), &q.profile()));
    RUBBLE_TRY(fillRange(c, q.status(), 0u, RUBBLE_STATUS_IMPULSES * sizeof(cl_uint),
                         sizeof(cl_uint), &q.profile()));
    const cl_uint impulseRoom = pairs.current.impulseRoom;
    RUBBLE_TRY(Dispatch(c, KernelId::SummarizePairs, &q.profile())
                   .with([&](Dispatch& d) { pairs.bindCurrent(d); })
                   .arg(pairs.manifolds)
                   .arg(b.jacobi)
                   .arg(b.poses)
                   .arg(b.velocities)
                   .arg(b.atStart)
                   .arg(b.surfaces)
                   .with([&](Dispatch& d) { bindRowSettings(d, pairs, params); })
                   .arg(pairs.summaries)
                   .arg(pairs.current.impulseCount)
                   .arg(pairs.current.impulseStart)
                   .arg(impulseRoom)
                   .arg(pairs.current.impulses)
                   .arg(pushed_)
                   .arg(q.status())
                   .run(pairs.strideItems(q), c.workSizes().pairGroup));
    return joints.prepare(q, b, params.solver.warmStart, params.dt);
}

Status PgsSolve::buildRows(StageQueue& q, DeviceBodies& b, PairStore& pairs,
                           const StepParams& params) {
    const Context& c = q.c();
    // The build order's entries: the pairs with rows (the step's elements after the joints), or
    // every pair the device's plan has room for.
    const cl_uint count = buildCount_;
    if (count == 0) return {};
    RUBBLE_TRY(Dispatch(c, KernelId::BuildPgsRows, &q.profile())
                   .arg(count)
                   .arg(buildOrder_)
                   .arg(elements_)
                   .arg(pairs.manifolds)
                   .arg(b.poses)
                   .arg(b.velocities)
                   .arg(b.atStart)
                   .arg(b.jacobi)
                   .arg(b.surfaces)
                   .with([&](Dispatch& d) { bindRowSettings(d, pairs, params); })
                   .arg(normalRows_)
                   .arg(frictionRows_)
                   .arg(impulses_)
                   .arg(pairs.current.impulseStart)
                   .arg(pairs.current.impulses)
                   .run(count, c.workSizes().pairGroup));
    // Per element its record, manifold, both bodies' poses, velocities, JacobiBody and surfaces,
    // last step's run of impulses (at most four) and its start; per point its rows, impulses and
    // key written.
    const std::uint64_t perElement = 3 * sizeof(cl_uint) + sizeof(shared::PgsElement) +
                                     sizeof(shared::ContactManifold) +
                                     2 * (sizeof(shared::BodyPose) + sizeof(shared::BodyVelocity) +
                                          sizeof(shared::JacobiBody) + sizeof(shared::float4)) +
                                     4 * sizeof(shared::PgsImpulse);
    const std::uint64_t perPoint = sizeof(shared::PgsNormalRow) + sizeof(shared::PgsFrictionRows) +
                                   sizeof(shared::float4) + sizeof(shared::PgsImpulse);
    q.profile().setLastBytes(count * perElement + rowCount_ * perPoint);
    return {};
}

Status PgsSolve::solve(StageQueue& q, DeviceBodies& b, PairStore& pairs, DeviceJoints& joints,
                       const DeviceStatus& st, const StepParams& params) {
    const Context& c = q.c();
    const SolverOptions& o = params.solver;
    const std::size_t group = c.workSizes().pairGroup;
    const cl_float relaxation = o.relaxation;
    const std::uint64_t rowBytes = sizeof(shared::PgsNormalRow) + sizeof(shared::PgsFrictionRows);
    RUBBLE_TRY(b.copyVelocities(q, b.before));
    if (o.warmStart) {
        for (const PgsLaunch& l : launches_) {
            RUBBLE_TRY(
                rowLaunch(q, KernelId::WarmStartPgs, l, joints, b).run(l.items(group), group));
            q.profile().setLastBytes(sweepBytes(l.count, l.points, rowBytes));
        }
    }
    // The split position pass, when a row pushes or may bounce (the coloring read the status
    // after the summaries), on push velocities that start at zero: its sweep k runs in the
    // launches of velocity sweep k, unless a row may bounce, whose target the velocity sweeps
    // decide (markBounces): then it runs after them.
    bounces_ = o.iterations > 0 && !launches_.empty() && st.bounces;
    pushes_ = o.iterations > 0 && !launches_.empty() && (st.pushes || bounces_);
    const bool pushes = pushes_, fused = fusedPushes();
    const std::size_t sweeps = std::size_t(std::max(o.iterations, 0));
    if (pushes) {
        const std::size_t n = b.count;
        RUBBLE_TRY(fill(c, push_, 0u, n * sizeof(shared::BodyVelocity), &q.profile()));
        RUBBLE_TRY(reserveGrowing(c, sweepResidual_, sweeps * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, sweepResidual_, 0u, sweeps * sizeof(cl_uint), &q.profile()));
    }
    for (int it = 0; it < o.iterations; ++it) {
        const cl_uint last = it + 1 == o.iterations ? 1u : 0u;
        const cl_uint pushSweep = fused ? cl_uint(it) : RUBBLE_PGS_NO_PUSH;
        for (const PgsLaunch& l : launches_) {
            RUBBLE_TRY(rowLaunch(q, KernelId::SolvePgs, l, joints, b)
                           .arg(relaxation)
                           .arg(last)
                           .arg(cl_uint(it))
                           .arg(pairs.current.impulses)
                           .arg(pairs.current.impulseStart)
                           .arg(q.status())
                           .arg(pushSweep)
                           .arg(pushed_)
                           .arg(push_)
                           .arg(sweepResidual_)
                           .run(l.items(group), group));
            // The push sweep reads the normal rows again (from cache), its velocities and
            // impulses, and both bodies' push marks.
            const std::uint64_t push =
                fused ? l.count * (4 * sizeof(shared::BodyVelocity) + 8) + l.points * 32 : 0;
            q.profile().setLastBytes(sweepBytes(l.count, l.points, rowBytes) + push +
                                     (last ? l.points * sizeof(shared::PgsImpulse) : 0));
        }
    }
    if (pushes && !fused) {
        // The rows that bounce aim the pass at their lift, then the pass on its own.
        const cl_uint count = elementRoom_;
        RUBBLE_TRY(Dispatch(c, KernelId::MarkBounces, &q.profile())
                       .arg(count)
                       .arg(elements_)
                       .arg(normalRows_)
                       .arg(impulses_)
                       .arg(pushed_)
                       .arg(q.status())
                       .run(count, group));
        q.profile().setLastBytes(count * sizeof(shared::PgsElement) +
                                 rowCount_ *
                                     (sizeof(shared::PgsNormalRow) + sizeof(shared::float4)));
        for (cl_uint sweep = 0; sweep < sweeps; ++sweep) {
            for (const PgsLaunch& l : launches_) {
                RUBBLE_TRY(launch(q, KernelId::PushPgs, l)
                               .arg(normalRows_)
                               .arg(impulses_)
                               .arg(pushed_)
                               .arg(push_)
                               .arg(relaxation)
                               .arg(sweep)
                               .arg(sweepResidual_)
                               .run(l.items(group), group));
                q.profile().setLastBytes(
                    l.count * (sizeof(shared::PgsElement) + 4 * sizeof(shared::BodyVelocity) + 8) +
                    l.points * (sizeof(shared::PgsNormalRow) + 2 * sizeof(shared::float4)));
            }
        }
    }
    // The layer pass, when the summaries found moving bodies that far apart in mass.
    if (!launches_.empty() && st.layers) {
        const std::size_t n = b.count;
        const std::size_t rows = std::max<std::size_t>(1, rowRoom_);
        RUBBLE_TRY(reserveGrowing(c, layer_, n * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, loaded_, n * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, layerHistogram_, (n + 1) * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, layerRows_, rows * sizeof(cl_uint)));
        RUBBLE_TRY(reserveGrowing(c, layerSorted_, rows * sizeof(cl_uint)));
        const cl_uint count = elementRoom_, bodyCount = b.count;
        const cl_uint jointCount = joints.count, pushPass = pushes ? 1u : 0u;
        RUBBLE_TRY(Dispatch(c, KernelId::LayerPgs, &q.profile())
                       .arg(count)
                       .arg(elements_)
                       .arg(normalRows_)
                       .arg(impulses_)
                       .arg(b.jacobi)
                       .arg(bodyCount)
                       .arg(joints.joints)
                       .arg(jointCount)
                       .arg(b.velocities)
                       .arg(pushPass)
                       .arg(pushed_)
                       .arg(push_)
                       .arg(q.status())
                       .arg(layer_)
                       .arg(loaded_)
                       .arg(layerRows_)
                       .arg(layerSorted_)
                       .arg(layerHistogram_)
                       .run(1, 1));
        // At least: every element and row read once, each body's layer and marks.
        q.profile().setLastBytes(count * sizeof(shared::PgsElement) +
                                 rowCount_ * sizeof(shared::PgsNormalRow) +
                                 n * (sizeof(shared::JacobiBody) + 2 * sizeof(cl_uint)));
    }
    if (bounces_) {
        RUBBLE_TRY(reserveGrowing(c, solved_, b.count * sizeof(shared::BodyVelocity)));
        RUBBLE_TRY(b.copyVelocities(q, solved_));
    }
    return absorbVelocityChange(q, b);
}

Status PgsSolve::bounce(StageQueue& q, DeviceBodies& b, const StepParams& params) {
    if (!bounces_) return {};
    const Context& c = q.c();
    const std::size_t group = c.workSizes().pairGroup;
    const std::size_t sweeps = std::size_t(std::max(params.solver.iterations, 0));
    RUBBLE_TRY(reserveGrowing(c, bounce_, std::max<std::size_t>(1, rowRoom_) * sizeof(float)));
    RUBBLE_TRY(reserveGrowing(c, bounceResidual_, sweeps * sizeof(cl_uint)));
    RUBBLE_TRY(fill(c, bounceResidual_, 0u, sweeps * sizeof(cl_uint), &q.profile()));
    // Per launch: each element's record and bodies' velocities read and written, each point's
    // normal row and impulses read, its bounce impulse read and written.
    auto bytes = [](const PgsLaunch& l) -> std::uint64_t {
        return l.count * (sizeof(shared::PgsElement) + 4 * sizeof(shared::BodyVelocity)) +
               l.points * (sizeof(shared::PgsNormalRow) + sizeof(shared::float4) + 8);
    };
    for (cl_uint sweep = 0; sweep < sweeps; ++sweep) {
        for (const PgsLaunch& l : launches_) {
            RUBBLE_TRY(launch(q, KernelId::BouncePgs, l)
                           .arg(normalRows_)
                           .arg(impulses_)
                           .arg(bounce_)
                           .arg(solved_)
                           .arg(sweep)
                           .arg(bounceResidual_)
                           .run(l.items(group), group));
            q.profile().setLastBytes(bytes(l));
        }
    }
    for (const PgsLaunch& l : launches_) {
        RUBBLE_TRY(launch(q, KernelId::BounceMomenta, l)
                       .arg(normalRows_)
                       .arg(impulses_)
                       .arg(bounce_)
                       .arg(b.momenta)
                       .arg(b.masses)
                       .arg(b.poses)
                       .arg(b.velocities)
                       .run(l.items(group), group));
        q.profile().setLastBytes(bytes(l) +
                                 l.count * 2 *
                                     (2 * sizeof(shared::BodyMomentum) + sizeof(shared::BodyMass) +
                                      sizeof(shared::BodyPose)));
    }
    return {};
}

Status PgsSolve::applyPushes(StageQueue& q, DeviceBodies& b, float dt) {
    // The kernel moves nothing unless a row pushed (the status block says, after markBounces).
    if (!pushes_) return {};
    const cl_uint count = b.count;
    const cl_float step = dt;
    return Dispatch(q.c(), KernelId::ApplyPushes, &q.profile())
        .arg(count)
        .arg(q.status())
        .arg(b.jacobi)
        .arg(push_)
        .arg(b.momenta)
        .arg(b.masses)
        .arg(b.poses)
        .arg(b.velocities)
        .arg(step)
        .run(count, RUBBLE_GROUP_BODIES);
}

Result<std::vector<shared::PgsNormalRow>> PgsSolve::downloadNormalRows(StageQueue& q) const {
    return download<shared::PgsNormalRow>(q.c(), normalRows_, rowCount_);
}

Result<std::vector<shared::PgsFrictionRows>> PgsSolve::downloadFrictionRows(StageQueue& q) const {
    return download<shared::PgsFrictionRows>(q.c(), frictionRows_, rowCount_);
}

} // namespace rubble::gpu
