// host/gpu/soft_step.cpp: dispatch of the soft step on the device: the soft points, then per
// substep the forces' share, warm start, the biased pass, the motion and the relax passes (one
// launch per block set and per color, as the PGS sweeps), then restitution and the step's end.
// The CPU twin is SoftStepSolver (host/dynamics/soft_step_solver.cpp).
#include "host/gpu/soft_step.h"

#include <algorithm>

#include "rubble/shared/soft_step.h"

namespace rubble::gpu {
namespace {

// A contact against a body that does not move is this many times as stiff (the CPU's
// kStillContactHertzScale).
constexpr float kStillHertzScale = RUBBLE_SOFT_STILL_HERTZ_SCALE;

} // namespace

SoftStepLaunch makeSoftStepLaunch(const SolverOptions& o, float dt) {
    SoftStepLaunch s;
    s.substeps = std::uint32_t(std::max(o.substeps, 1));
    s.relaxIterations = std::uint32_t(std::max(o.relaxIterations, 0));
    s.h = dt / float(s.substeps);
    s.inverseH = 1.0f / s.h;
    // Stiffer than a quarter of the substep rate, a substep cannot follow the spring.
    const float hertz = std::min(o.contactHertz, 0.25f / s.h);
    s.contactSoft = shared::softnessItem(hertz, o.dampingRatio, s.h);
    s.stillSoft = shared::softnessItem(kStillHertzScale * hertz, o.dampingRatio, s.h);
    s.jointSoft = shared::softnessItem(o.jointHertz, o.jointDampingRatio, s.h);
    s.maxPushSpeed = o.maxPushSpeed;
    s.restitutionThreshold = RUBBLE_RESTITUTION_THRESHOLD;
    return s;
}

Status SoftStepSolve::create(StageQueue& q, std::uint32_t bodies) {
    const Context& c = q.c();
    const std::size_t n = std::max<std::uint32_t>(bodies, 1);
    RUBBLE_TRY(share_.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(softPoses_.reserve(c.context(), n * sizeof(shared::BodyPose)));
    return moved_.reserve(c.context(), n * sizeof(shared::float4));
}

Status SoftStepSolve::solve(StageQueue& q, DeviceBodies& b, const PgsSolve& pgs, PairStore& pairs,
                            DeviceJoints& joints, const StepParams& params) {
    const Context& c = q.c();
    const std::size_t group = c.workSizes().pairGroup;
    const SoftStepLaunch s = makeSoftStepLaunch(params.solver, params.dt);
    const PgsSolve::RowBuffers rows = pgs.rowBuffers();
    const cl_uint count = b.count;
    // The velocities after the forces, for the momenta at the end.
    RUBBLE_TRY(b.copyVelocities(q, b.before));
    const cl_uint pairElements = pgs.pairElements();
    if (pairElements > 0) {
        RUBBLE_TRY(reserveGrowing(
            c, contacts_, std::max<std::size_t>(1, pgs.rowRoom()) * sizeof(shared::SoftContact)));
        RUBBLE_TRY(Dispatch(c, KernelId::PrepareSoftContacts, &q.profile())
                       .arg(pairElements)
                       .arg(rows.buildOrder)
                       .arg(rows.elements)
                       .arg(pairs.manifolds)
                       .arg(b.poses)
                       .arg(b.atStart)
                       .arg(b.surfaces)
                       .arg(contacts_)
                       .run(pairElements, group));
    } else {
        RUBBLE_TRY(reserveGrowing(c, contacts_, sizeof(shared::SoftContact)));
    }
    const cl_float shareOfForces = 1.0f / float(s.substeps);
    RUBBLE_TRY(Dispatch(c, KernelId::BeginSoftStep, &q.profile())
                   .arg(count)
                   .arg(b.jacobi)
                   .arg(b.poses)
                   .arg(b.atStart)
                   .arg(b.velocities)
                   .arg(share_)
                   .arg(softPoses_)
                   .arg(moved_)
                   .arg(shareOfForces)
                   .run(count, RUBBLE_GROUP_BODIES));
    const std::span<const PgsLaunch> launches = pgs.launches();
    // A launch of a pass kernel with the plan's arguments bound first.
    auto launch = [&](KernelId id, const PgsLaunch& l) {
        Dispatch d(c, id, &q.profile());
        d.arg(l.first).arg(l.count).arg(l.mode).arg(rows.elements).arg(rows.blockStarts);
        return d;
    };
    const shared::float4 settings =
        shared::make4(s.inverseH, s.maxPushSpeed, s.restitutionThreshold, 0.0f);
    const std::uint32_t passes = 1 + s.relaxIterations;
    auto pass = [&](cl_uint useBias, cl_uint lastPass) -> Status {
        for (const PgsLaunch& l : launches)
            RUBBLE_TRY(launch(KernelId::SolveSoft, l)
                           .arg(rows.normalRows)
                           .arg(rows.frictionRows)
                           .arg(rows.impulses)
                           .arg(contacts_)
                           .arg(joints.joints)
                           .arg(joints.rows)
                           .arg(b.jacobi)
                           .arg(softPoses_)
                           .arg(moved_)
                           .arg(b.velocities)
                           .arg(s.contactSoft)
                           .arg(s.stillSoft)
                           .arg(s.jointSoft)
                           .arg(settings)
                           .arg(useBias)
                           .arg(lastPass)
                           .arg(q.status())
                           .run(l.items(group), group));
        return {};
    };
    const cl_float h = s.h;
    for (std::uint32_t sub = 0; sub < s.substeps; ++sub) {
        const bool lastSubstep = sub + 1 == s.substeps;
        // beginSoftStep added the first substep's share.
        if (sub > 0)
            RUBBLE_TRY(Dispatch(c, KernelId::AddSoftForces, &q.profile())
                           .arg(count)
                           .arg(b.jacobi)
                           .arg(share_)
                           .arg(b.velocities)
                           .run(count, RUBBLE_GROUP_BODIES));
        for (const PgsLaunch& l : launches)
            RUBBLE_TRY(launch(KernelId::WarmStartSoft, l)
                           .arg(rows.normalRows)
                           .arg(rows.frictionRows)
                           .arg(rows.impulses)
                           .arg(joints.joints)
                           .arg(joints.rows)
                           .arg(b.jacobi)
                           .arg(softPoses_)
                           .arg(b.velocities)
                           .run(l.items(group), group));
        RUBBLE_TRY(pass(1u, lastSubstep && passes == 1 ? 1u : 0u));
        RUBBLE_TRY(Dispatch(c, KernelId::IntegrateSoft, &q.profile())
                       .arg(count)
                       .arg(b.jacobi)
                       .arg(b.velocities)
                       .arg(h)
                       .arg(softPoses_)
                       .arg(moved_)
                       .run(count, RUBBLE_GROUP_BODIES));
        for (std::uint32_t k = 0; k < s.relaxIterations; ++k)
            RUBBLE_TRY(pass(0u, lastSubstep && k + 1 == s.relaxIterations ? 1u : 0u));
    }
    const cl_float threshold = s.restitutionThreshold;
    for (const PgsLaunch& l : launches)
        RUBBLE_TRY(launch(KernelId::BounceSoft, l)
                       .arg(rows.normalRows)
                       .arg(rows.frictionRows)
                       .arg(rows.impulses)
                       .arg(contacts_)
                       .arg(b.velocities)
                       .arg(threshold)
                       .arg(pairs.current.impulses)
                       .arg(pairs.current.impulseStart)
                       .run(l.items(group), group));
    return Dispatch(c, KernelId::FinishSoftStep, &q.profile())
        .arg(count)
        .arg(q.status())
        .arg(b.jacobi)
        .arg(b.masses)
        .arg(softPoses_)
        .arg(b.before)
        .arg(b.velocities)
        .arg(b.momenta)
        .arg(b.poses)
        .run(count, RUBBLE_GROUP_BODIES);
}

} // namespace rubble::gpu
