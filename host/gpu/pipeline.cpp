// host/gpu/pipeline.cpp: the device arrays of a world, their transfers, and the device step as
// a list of stages enqueued without waiting; the host meets the step once, at its end, and
// reads each stage's device time from the profiling events.
#include "host/gpu/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <utility>

#include "host/core/assert.h"
#include "host/core/clock.h"
#include "host/core/limits.h"
#include "host/core/math.h"

namespace rubble::gpu {

void PipelineDeleter::operator()(Pipeline* p) const { delete p; }

Result<PipelineHandle> Pipeline::create(std::shared_ptr<Context> context,
                                        const PipelineInput& in) {
    const BodiesView bodies = in.bodies;
    const std::span<const std::uint8_t> kinematic = in.kinematic;
    const std::size_t n = bodies.count();
    if (n >= RUBBLE_TAG_MAX_BODIES)
        return makeError(ErrorKind::NotSupported, "bodies",
                         "the OpenCL pipeline takes fewer than " +
                             std::to_string(RUBBLE_TAG_MAX_BODIES) + " bodies; this world has " +
                             std::to_string(n));
    PipelineHandle p(new Pipeline(std::move(context)));
    const Context& c = *p->context_;
    p->bodies_.count = std::uint32_t(n);
    p->deterministic_ = in.deterministic;
    p->particlePgs_ = in.collision == CollisionMethod::Particles && in.particlePgs;
    p->pgsBlocks_ = in.pgsBlocks >= 0 ? std::uint32_t(in.pgsBlocks)
                                      : defaultPgsBlocks(c.workSizes().pgsBlocks, n);
    p->lcpStride_ = lcpStride(in.surfaces, bodies.masses);
    p->kinematic_.assign(n, 0);
    std::copy(kinematic.begin(), kinematic.begin() + std::min(kinematic.size(), n),
              p->kinematic_.begin());
    RUBBLE_TRY(p->bodies_.atStart.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(p->bodies_.before.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(p->bodies_.jacobi.reserve(c.context(), n * sizeof(shared::JacobiBody)));
    RUBBLE_TRY(p->bodies_.slowFor.reserve(c.context(), n * sizeof(cl_float)));
    RUBBLE_TRY(p->bodies_.restless.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(fill(c, p->bodies_.slowFor, 0u, n * sizeof(cl_float)));
    RUBBLE_TRY(fill(c, p->bodies_.restless, 0u, n * sizeof(cl_uint)));
    RUBBLE_TRY(upload(c, p->bodies_.forces, bodies.forces));
    // SAT sleeps as the host decides (the world's islands) when it is given a HostSleep.
    if (in.collision == CollisionMethod::Sat) p->islands_.sleep = in.hostSleep;
    RUBBLE_TRY(p->status_.reserve(c.context(), RUBBLE_STATUS_COUNT * sizeof(cl_uint)));
    RUBBLE_TRY(p->uploadBodies(bodies));
    RUBBLE_TRY(p->uploadParticles(in.particles, bodies, in.surfaces));
    if (in.collision == CollisionMethod::Sat) RUBBLE_TRY(p->createSat(in));
    // Particles with PGS: a pair of one point per contact, as many pairs as contacts.
    if (p->particlePgs_) RUBBLE_TRY(p->createPairArrays(in, p->contacts_.capacity));

    // The host's bodies, in index order: the order of each step's obstacle states.
    std::vector<cl_uint> obstacles;
    for (std::uint32_t i = 0; i < n; ++i)
        if (p->kinematic_[i]) obstacles.push_back(i);
    ObstacleBuffers& o = p->obstacles_;
    o.count = std::uint32_t(obstacles.size());
    RUBBLE_TRY(upload(c, o.bodies, obstacles));
    RUBBLE_TRY(o.states.reserve(c.context(), obstacles.size() * sizeof(shared::ObstacleState)));
    RUBBLE_TRY(o.impulses.reserve(c.context(), obstacles.size() * sizeof(shared::BodyImpulse)));
    p->obstaclesHost_.resize(obstacles.size());
    p->impulsesHost_.assign(obstacles.size(), shared::BodyImpulse{});

    // A status block that stages run alone (twin tests) can read.
    p->statusHost_ = p->statusInit_;
    RUBBLE_TRY(upload(c, p->status_, std::span<const cl_uint>(p->statusInit_)));
    RUBBLE_TRY(p->finish());
    return p;
}

Status Pipeline::uploadMassesAndFlags(std::span<const shared::BodyMass> hostMasses) {
    const Context& c = *context_;
    hostBodies_ = true;
    // Kinematic bodies are walls on the device; their flags are the host's to set each step.
    std::vector<shared::BodyMass> masses(hostMasses.begin(), hostMasses.end());
    std::vector<cl_uint> flags(masses.size());
    for (std::size_t i = 0; i < masses.size(); ++i) {
        flags[i] = masses[i].flags & (RUBBLE_BODY_STATIC | RUBBLE_BODY_ASLEEP);
        if (!kinematic_[i]) continue;
        masses[i] = shared::wallMassItem(masses[i]);
        flags[i] = RUBBLE_BODY_KINEMATIC;
    }
    movingBodies_ = 0;
    for (std::size_t i = 0; i < masses.size(); ++i)
        if (!kinematic_[i] && !(masses[i].flags & RUBBLE_BODY_STATIC)) ++movingBodies_;
    if (islands_.enabled()) {
        // The host's flags are the islands' from here on (a body woken by the host wakes its
        // island; updateSleep sees it as woken from outside).
        islands_.masses = masses;
        islands_.asleep = 0;
        for (std::size_t i = 0; i < masses.size(); ++i)
            if (!kinematic_[i] && (masses[i].flags & RUBBLE_BODY_ASLEEP)) ++islands_.asleep;
    }
    RUBBLE_TRY(upload(c, bodies_.masses, masses));
    return upload(c, bodies_.flags, flags);
}

Status Pipeline::uploadBodies(BodiesView bodies) {
    const Context& c = *context_;
    hostBodies_ = true;
    RUBBLE_TRY(upload(c, bodies_.poses, bodies.poses));
    RUBBLE_TRY(upload(c, bodies_.velocities, bodies.velocities));
    // Stages run alone (twin tests) see the host's velocities as those before the forces.
    RUBBLE_TRY(upload(c, bodies_.atStart, bodies.velocities));
    RUBBLE_TRY(upload(c, bodies_.momenta, bodies.momenta));
    return uploadMassesAndFlags(bodies.masses);
}

Status Pipeline::enqueueBodyRead(Bodies bodies, Profile* profile) {
    const Context& c = *context_;
    flagsHost_.resize(bodies_.count);
    RUBBLE_TRY(enqueueDownload(c, bodies_.poses, bodies.poses, profile));
    RUBBLE_TRY(enqueueDownload(c, bodies_.velocities, bodies.velocities, profile));
    RUBBLE_TRY(enqueueDownload(c, bodies_.momenta, bodies.momenta, profile));
    return enqueueDownload(c, bodies_.flags, std::span(flagsHost_), profile);
}

void Pipeline::takeSleepFlags(Bodies bodies) const {
    for (std::size_t i = 0; i < flagsHost_.size(); ++i) {
        if (kinematic_[i]) continue; // the host's own flags
        bodies.masses[i].flags = (bodies.masses[i].flags & ~RUBBLE_BODY_ASLEEP) |
                                 (flagsHost_[i] & RUBBLE_BODY_ASLEEP);
    }
}

Status Pipeline::downloadBodies(Bodies bodies) {
    RUBBLE_TRY(enqueueBodyRead(bodies, nullptr));
    RUBBLE_TRY(finish());
    takeSleepFlags(bodies);
    return {};
}

Status Pipeline::downloadPoses(std::uint32_t first, std::uint32_t count, void* out) {
    RUBBLE_ASSERT(std::size_t(first) + count <= bodies_.count);
    return readBytes(*context_, bodies_.poses, first * sizeof(shared::BodyPose), out,
                     count * sizeof(shared::BodyPose), Wait::Done);
}

Status Pipeline::writeStatusSlot(std::uint32_t slot, cl_uint value) {
    return writeBytes(*context_, status_, slot * sizeof(cl_uint), &value, sizeof value,
                      Wait::Done);
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
                                        0, bytes, 0, nullptr,
                                        profile_.transfer(Transfer::Copy, bytes)));
    return {};
}

std::size_t Pipeline::strideItems(std::uint32_t capacity, std::size_t group) const {
    const std::size_t units = std::max<std::uint32_t>(1, context_->device().computeUnits);
    return std::min(units * RUBBLE_STRIDE_GROUPS_PER_UNIT * group, roundUp(capacity, group));
}

Status Pipeline::resetStatus() {
    statusInit_ = {};
    statusInit_[RUBBLE_STATUS_NONFINITE] = 0xffffffffu;
    // The SAT method's manifolds live per pair: its contacts never overflow.
    statusInit_[RUBBLE_STATUS_CAPACITY] = sat_.enabled ? 0xffffffffu : contacts_.capacity;
    // Non-blocking: statusInit_ stays put until the step is met.
    return enqueueUpload(*context_, status_, std::span<const cl_uint>(statusInit_), &profile_);
}

DeviceStatus Pipeline::statusFromSlots() const {
    const std::array<cl_uint, RUBBLE_STATUS_COUNT>& slots = statusHost_;
    DeviceStatus d;
    d.contacts = slots[RUBBLE_STATUS_CONTACTS];
    d.firstNonFinite = slots[RUBBLE_STATUS_NONFINITE];
    std::memcpy(&d.largestPenetration, &slots[RUBBLE_STATUS_PENETRATION], sizeof(float));
    std::memcpy(&d.solverResidual, &slots[RUBBLE_STATUS_RESIDUAL], sizeof(float));
    d.capacity = slots[RUBBLE_STATUS_CAPACITY];
    d.asleep = slots[RUBBLE_STATUS_ASLEEP];
    d.woken = slots[RUBBLE_STATUS_WOKEN];
    d.pairs = slots[RUBBLE_STATUS_PAIRS];
    d.gridEntries = slots[RUBBLE_STATUS_GRID_ENTRIES];
    d.largeBodies = slots[RUBBLE_STATUS_LARGE];
    d.kept = slots[RUBBLE_STATUS_KEPT];
    d.carried = slots[RUBBLE_STATUS_CARRIED];
    return d;
}

Result<DeviceStatus> Pipeline::readStatus() {
    // Timed: in a step it is the device's work while the host waits (a read outside a step is
    // dropped with the records at the next beginStep).
    RUBBLE_TRY(download(*context_, status_, std::span<cl_uint>(statusHost_), &profile_));
    return statusFromSlots();
}

Status Pipeline::finish() {
    RUBBLE_CL_CHECK(clFinish(context_->queue()));
    return {};
}

Status Pipeline::beginStep(const StepParams& params, const StepInputs& in) {
    RUBBLE_ASSERT(!stepPending_);
    const float dt = params.dt;
    profile_.discard();
    profile_.setStage(DeviceStage::ApplyForces);
    RUBBLE_TRY(resetStatus());
    islands_.stepRead = false;
    if (obstacles_.count > 0) RUBBLE_TRY(placeObstacles(in.obstacles));
    for (const EventDesc& e : in.explosions) RUBBLE_TRY(applyExplosion(e));
    profile_.setStage(DeviceStage::IntegrateVelocities);
    // The velocities before the forces (atStart): restitution's approach, explicit Euler's motion.
    RUBBLE_TRY(integrateVelocities(params.gravity, dt));
    gatherImpulses_ = in.gatherObstacleImpulses && obstacles_.count > 0;
    if (sat_.enabled) {
        // SAT and PGS: the host waits once, after the rows, to color them.
        RUBBLE_TRY(enqueueSatCollision(params));
        RUBBLE_TRY(enqueueSatSolve(params));
    } else if (particlePgs_) {
        // Particles and PGS: the same, from the particles' contacts.
        profile_.setStage(DeviceStage::BroadPhase);
        RUBBLE_TRY(transformParticles());
        RUBBLE_TRY(buildGrid());
        RUBBLE_TRY(enqueueParticlePgs(params));
        RUBBLE_TRY(enqueueSatSolve(params));
    } else {
        profile_.setStage(DeviceStage::BroadPhase);
        RUBBLE_TRY(transformParticles());
        RUBBLE_TRY(buildGrid());
        RUBBLE_TRY(enqueueFromCollision(params));
    }
    readBack_ = in.readBack;
    if (readBack_) {
        RUBBLE_TRY(enqueueBodyRead(*readBack_, &profile_));
        RUBBLE_CL_CHECK(clFlush(context_->queue()));
    }
    stepPending_ = true;
    return {};
}

Status Pipeline::enqueueSatCollision(const StepParams& params) {
    std::uint32_t woken = 0;
    for (std::uint32_t round = 1;; ++round) {
        profile_.setStage(DeviceStage::BroadPhase);
        RUBBLE_TRY(broadPhase(params.dt));
        profile_.setStage(DeviceStage::NarrowPhase);
        RUBBLE_TRY(narrowPhase(params.dt));
        Result<DeviceStatus> st = wakeAndSummarize(params, round);
        RUBBLE_TRY(st);
        if (st->pairs <= sat_.current.capacity && islands_.enabled()) {
            // The CPU's wake: the islands a restless body touches wake, and the collision runs
            // again for their pairs with sleeping bodies, until a round wakes none.
            profile_.setStage(DeviceStage::Sleep);
            Result<std::uint32_t> islandsWoken = wakeIslandsOnHost();
            RUBBLE_TRY(islandsWoken);
            profile_.setStage(DeviceStage::BuildContactRows);
            if (*islandsWoken > 0) continue;
            pairsFound_ = st->pairs;
            break;
        }
        if (st->pairs <= sat_.current.capacity) {
            if (st->woken == woken) {
                pairsFound_ = st->pairs;
                break;
            }
            // The wake reaches through the sleeping bodies that rest against the woken ones (last
            // step's entries with impulses), a round a launch, until a round wakes none; then
            // the collision runs again, as the woken bodies' pairs with sleeping ones were not
            // found.
            woken = st->woken;
            profile_.setStage(DeviceStage::Sleep);
            for (;;) {
                RUBBLE_TRY(wakeStillPairs(++round));
                Result<DeviceStatus> spread = readStatus();
                RUBBLE_TRY(spread);
                if (spread->woken == woken) break;
                woken = spread->woken;
            }
            continue;
        }
        // Nothing has moved (the wake only woke bodies): grow and find them again, within the
        // step's pair budget (host/core/limits.h), as the CPU's broad phase is held to it.
        woken = st->woken;
        const std::size_t budget = pairBudget(bodies_.count);
        if (st->pairs > budget)
            return limitError("broadPhase", "broad-phase pairs", st->pairs, budget, params.step + 1,
                              "bodies overlap each other in large numbers");
        const auto grown = std::uint32_t(std::min<std::size_t>(st->pairs + st->pairs / 2, budget));
        std::fprintf(stderr,
                     "rubble: pair overflow (%u pairs, room for %u): buffers grown to %u "
                     "and the step's collision run again\n",
                     st->pairs, sat_.current.capacity, grown);
        RUBBLE_TRY(setPairCapacity(grown));
    }
    RUBBLE_TRY(colorPgs());
    return buildPgsRows(params);
}

Result<DeviceStatus> Pipeline::wakeAndSummarize(const StepParams& params, std::uint32_t round) {
    // Sleeping bodies hit in this step wake before the rows, so that their mass takes part.
    profile_.setStage(DeviceStage::Sleep);
    if (!islands_.enabled()) RUBBLE_TRY(wakeTouchedPairs(round));
    profile_.setStage(DeviceStage::BuildContactRows);
    RUBBLE_TRY(summarizePairs(params));
    return readStatus();
}

Status Pipeline::enqueueParticlePgs(const StepParams& params) {
    for (;;) {
        profile_.setStage(DeviceStage::NarrowPhase);
        RUBBLE_TRY(collideParticles());
        RUBBLE_TRY(sortContacts(true));
        RUBBLE_TRY(particlePairs());
        // Round 0: no wake reaches further than one contact (the collision runs again only
        // after an overflow).
        Result<DeviceStatus> st = wakeAndSummarize(params, 0);
        RUBBLE_TRY(st);
        if (st->contacts <= st->capacity) break;
        // The stages after collision saw no contacts: grow the buffers (the pairs' with them)
        // and collide again.
        RUBBLE_TRY(growContacts(*st, params.step + 1, "the step's collision"));
    }
    RUBBLE_TRY(colorPgs());
    return buildPgsRows(params);
}

Status Pipeline::enqueueSatSolve(const StepParams& params) {
    const float dt = params.dt;
    profile_.setStage(DeviceStage::Solve);
    RUBBLE_TRY(solvePgs(params));
    profile_.setStage(DeviceStage::IntegratePositions);
    // Without a bounce nothing between the two reads the velocities applyPushes derives again.
    RUBBLE_TRY(integratePositions(dt, params.symplectic(), pgs_.fusedPushes()));
    // As PgsSolver::solvePositions: bounces from the contact, the pushes, the joints.
    RUBBLE_TRY(bouncePgs(params));
    RUBBLE_TRY(applyPushes(dt));
    RUBBLE_TRY(projectJoints());
    RUBBLE_TRY(clearForces());
    profile_.setStage(DeviceStage::Sleep);
    // Islands on the host decide once the step is met (updateIslandsOnHost).
    if (!islands_.enabled() && params.sleep) RUBBLE_TRY(sleepBodies(dt));
    // This step's pairs, features and impulses are the next step's. With SAT, a step that found
    // no pairs after one that found none, with no body state from the host between, keeps last
    // step's set as it is: it holds still pairs only, and none of them can have moved (a moving
    // body finds the pairs of the bodies it rests against), so the carry would copy it whole.
    const bool stillSet = sat_.enabled && pairsFound_ == 0 && keptFound_ == 0 && !hostBodies_;
    if (!stillSet) {
        RUBBLE_TRY(keepPairFeatures());
        keptFound_ = pairsFound_;
    }
    hostBodies_ = false;
    warmSwapped_ = false;
    return enqueueStatusRead();
}

Status Pipeline::enqueueFromCollision(const StepParams& params) {
    const float dt = params.dt;
    const bool symplectic = params.symplectic();
    const SolverOptions& solver = params.solver;
    // lcp-jacobi sizes its dense problem on the host: it waits here for the contact count.
    const bool dense = solver.type == SolverType::LcpJacobi;
    profile_.setStage(DeviceStage::NarrowPhase);
    RUBBLE_TRY(collideParticles());
    if (dense) RUBBLE_TRY(readContactCount());
    if (deterministic_) RUBBLE_TRY(sortContacts());
    // Sleeping bodies hit in this step wake before the rows, so that their mass takes part.
    profile_.setStage(DeviceStage::Sleep);
    RUBBLE_TRY(wakeTouched());
    profile_.setStage(DeviceStage::BuildContactRows);
    RUBBLE_TRY(buildJacobiRows(params.rows, solver.warmStart));
    profile_.setStage(DeviceStage::Solve);
    // lcp-jacobi solves the dense problem; the Jacobi stage then only applies its impulses.
    if (dense)
        RUBBLE_TRY(solveLcpJacobi(lcpStride_, solver.iterations, params.lcpJacobiRelaxation));
    RUBBLE_TRY(solveJacobi(dense ? 0 : solver.iterations, params.jacobiRelaxation, false));
    profile_.setStage(DeviceStage::IntegratePositions);
    RUBBLE_TRY(integratePositions(dt, symplectic));
    RUBBLE_TRY(clearForces());
    profile_.setStage(DeviceStage::Sleep);
    if (params.sleep) RUBBLE_TRY(sleepBodies(dt));
    if (gatherImpulses_) RUBBLE_TRY(gatherObstacleImpulses());
    // This step's contacts and impulses become the next step's warm start.
    warmSwapped_ = false;
    if (solver.warmStart) {
        std::swap(contacts_.contacts, contacts_.previous);
        std::swap(contacts_.rows, contacts_.previousRows);
        warmSwapped_ = true;
        // The swapped-in buffers must still hold a full step.
        RUBBLE_TRY(setContactCapacity(contacts_.capacity, contacts_.growable));
    }
    return enqueueStatusRead();
}

Status Pipeline::clearForces() {
    if (!forcesOnDevice_) return {};
    forcesOnDevice_ = false;
    return fill(*context_, bodies_.forces, 0u,
                std::size_t(bodies_.count) * sizeof(shared::BodyForce), &profile_);
}

Status Pipeline::enqueueStatusRead() {
    // Non-blocking: statusHost_ stays put until the step is met.
    RUBBLE_TRY(enqueueDownload(*context_, status_, std::span<cl_uint>(statusHost_), &profile_));
    RUBBLE_CL_CHECK(clFlush(context_->queue()));
    return {};
}

void Pipeline::undoWarmStartSwap() {
    if (!warmSwapped_) return;
    std::swap(contacts_.contacts, contacts_.previous);
    std::swap(contacts_.rows, contacts_.previousRows);
    warmSwapped_ = false;
}

Status Pipeline::endStep(const StepParams& params, std::span<const std::string> names,
                         StepStats& stats) {
    RUBBLE_ASSERT(stepPending_);
    stepPending_ = false;
    // The step's read-back, if it asked for one (its arrays are the caller's till we return).
    const std::optional<Bodies> readBack = std::exchange(readBack_, std::nullopt);
    const auto waitStart = std::chrono::steady_clock::now();
    RUBBLE_TRY(finish());
    stats.deviceWaitMs = msSince(waitStart);
    for (;;) {
        const DeviceStatus st = statusFromSlots();
        if (st.contacts <= st.capacity) break;
        // The stages after collision did nothing: grow the buffer and run them again.
        undoWarmStartSwap();
        if (Status grown = growContacts(st, params.step + 1, "the step's contact stages");
            !grown.ok()) {
            profile_.discard();
            return grown;
        }
        RUBBLE_TRY(enqueueFromCollision(params));
        if (readBack) RUBBLE_TRY(enqueueBodyRead(*readBack, &profile_));
        RUBBLE_TRY(finish());
    }
    DeviceStatus st = statusFromSlots();
    if (islands_.enabled() && params.sleep) {
        // The CPU's updateSleep on the step's velocities; the stopped bodies go to the device.
        profile_.setStage(DeviceStage::Sleep);
        const auto islandsStart = std::chrono::steady_clock::now();
        Result<std::uint32_t> asleep = updateIslandsOnHost(params.dt, readBack);
        RUBBLE_TRY(asleep);
        st.asleep = *asleep;
        stats.islandsMs = msSince(islandsStart);
    }
    if (readBack) takeSleepFlags(*readBack);
    TrafficCounts traffic;
    traffic.bodies = bodies_.count;
    traffic.particles = particles_.count;
    traffic.cells = std::uint64_t(1) << particles_.bits;
    traffic.contacts = st.contacts;
    traffic.previous = params.solver.warmStart ? contacts_.previousCount : 0u;
    traffic.sortItems = context_->workSizes().sortItems;
    traffic.jointReal = context_->workSizes().jointRealBytes();
    if (pairPgs()) {
        traffic.pairs = st.pairs;
        traffic.gridEntries = st.gridEntries;
        traffic.largeBodies = st.largeBodies;
        traffic.planes = sat_.planeCount;
        traffic.kept = st.kept;
        traffic.carried = st.carried;
        traffic.joints = pgs_.jointCount;
        traffic.jointBodies = pgs_.jointBodyCount;
        traffic.directGroups = pgs_.directGroupCount;
        traffic.directMembers = pgs_.directMemberCount;
        traffic.directRows = pgs_.directRowCount;
        traffic.directMatrix = pgs_.directMatrixCount;
    }
    contacts_.count = st.contacts;
    if (warmSwapped_) contacts_.previousCount = st.contacts;
    Result<DeviceTimes> times = profile_.collect(traffic);
    RUBBLE_TRY(times);
    stats.deviceMs = times->busyMs;
    stats.deviceStages = times->stages;
    stats.deviceContactCount = st.contacts;
    stats.deviceAsleep = st.asleep;
    stats.asleep = st.asleep;
    stats.largestPenetration = std::max(stats.largestPenetration, st.largestPenetration);
    stats.solverResidual = std::max(stats.solverResidual, st.solverResidual);
    if (st.firstNonFinite < bodies_.count)
        return makeError(ErrorKind::Numerical, "body " + names[st.firstNonFinite],
                         "its state is not finite after step " + std::to_string(params.step + 1) +
                             " (t = " +
                             std::to_string(double(params.step + 1) * double(params.dt)) + " s)");
    return {};
}

} // namespace rubble::gpu
