// host/gpu/device_step.cpp: the device step as the list of its stages, enqueued without waiting;
// the host meets the step once, at its end, and reads each stage's device time from the
// profiling events. Three collision paths share the ends of the step: SAT (broad phase, narrow
// phase, the wake, PGS), particles with PGS (particle contacts as pairs of one point, PGS), and
// particles with the Jacobi family.
//
// A step run ahead (SAT, the device's plan): the host does not wait for the status after the
// summaries but assumes last step's round of it (the pairs and impulses fit, nothing woke, the
// same rows push, bounce and layer), keeps the step's start on the device, and checks the round
// once the step is met; a step whose round was not as assumed is put back to its start and runs
// again as a step that waits, so the result is always the waiting step's.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <utility>

#include "host/core/assert.h"
#include "host/core/clock.h"
#include "host/core/limits.h"
#include "host/gpu/integrate.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {
namespace {

// A buffer the device or the process had no room for (host/gpu/memory.h) names the stage that
// asked for it.
Status namingStage(Status s, const Profile& profile) {
    if (s.ok() || s.error().kind != ErrorKind::Limit || s.error().where != "device memory")
        return s;
    Error e = s.error();
    e.where = "device memory, stage " + std::string(stageName(profile.stage()));
    return e;
}

} // namespace

Status Pipeline::beginStep(const StepParams& params, const StepInputs& in) {
    queue_->profile().discard();
    waitsAtBegin_ = queue_->waits();
    return namingStage(enqueueStep(params, in), queue_->profile());
}

Status Pipeline::endStep(const StepParams& params, std::span<const std::string> names,
                         StepStats& stats) {
    return namingStage(meetStep(params, names, stats), queue_->profile());
}

Status Pipeline::enqueueStep(const StepParams& params, const StepInputs& in) {
    RUBBLE_ASSERT(!stepPending_);
    StageQueue& q = *queue_;
    Profile& profile = q.profile();
    profile.setStage(DeviceStage::ApplyForces);
    sumEnergy_ = in.sumEnergy;
    restartEnergy_ = in.restartEnergy;
    energySummed_ = false;
    ahead_ = mayRunAhead(in);
    uploaded_ = false;
    if (ahead_) {
        RUBBLE_TRY(pairs_.keepImpulseRoomAhead(q, lastRound_.impulses));
        RUBBLE_TRY(keepStepStart());
    }
    // The SAT method's manifolds live per pair: its contacts never overflow.
    RUBBLE_TRY(q.resetStatus(sat() ? 0xffffffffu : particles_.contacts().capacity));
    if (obstacles_.count() > 0) RUBBLE_TRY(obstacles_.place(q, bodies_, in.obstacles));
    if (!in.kinematicVelocities.empty()) {
        RUBBLE_TRY(targets_.setVelocities(q, bodies_, in.kinematicVelocities));
        // Body state from the host, as an upload is: last step's pairs may not hold.
        hostWrote_ = true;
    }
    for (const EventDesc& e : in.explosions) RUBBLE_TRY(applyExplosion(q, bodies_, e));
    profile.setStage(DeviceStage::IntegrateVelocities);
    RUBBLE_TRY(integrateVelocities(q, bodies_, params.gravity, params.dt));
    gatherImpulses_ = in.gatherObstacleImpulses && obstacles_.count() > 0;
    stepTargets_ = in.kinematicTargets;
    if (sat()) {
        // SAT and PGS: the host waits once, after the summaries, to plan the solve.
        RUBBLE_TRY(collideSat(params));
        RUBBLE_TRY(solvePairs(params));
    } else {
        profile.setStage(DeviceStage::BroadPhase);
        RUBBLE_TRY(particles_.transform(q, bodies_));
        RUBBLE_TRY(particles_.buildGrid(q, bodies_, sort_));
        if (particlePgs_) {
            RUBBLE_TRY(collideParticlePairs(params));
            RUBBLE_TRY(solvePairs(params));
        } else {
            RUBBLE_TRY(solveParticles(params));
        }
    }
    readBack_ = in.readBack;
    if (readBack_) {
        ++bodyReads_;
        RUBBLE_TRY(bodies_.enqueueRead(q, *readBack_, true));
        RUBBLE_CL_CHECK(clFlush(q.c().queue()));
    }
    stepPending_ = true;
    return {};
}

bool Pipeline::mayRunAhead(const StepInputs& in) const {
    // Nothing from the host (bodies, explosions, obstacles, kinematic motion; an upload also
    // resets the islands' host state), last step's round known and its set kept whole; the pair
    // sets of one size, so that the step's keep reallocates nothing and can be taken back.
    return sat() && pgs_.devicePlans() && roundKnown_ && !again_ && !uploaded_ && keptFound_ > 0 &&
           in.explosions.empty() && in.kinematicVelocities.empty() && in.kinematicTargets.empty() &&
           obstacles_.count() == 0 && pairs_.current.capacity == pairs_.previous.capacity &&
           pairs_.current.impulseRoom == pairs_.previous.impulseRoom;
}

Status Pipeline::keepStepStart() {
    // What a step reads from the step before and writes: the bodies, the joints' kept
    // impulses, the islands' state. Last step's pair set is only read; the levels of the
    // device's plan are two buffers taken in turn.
    stepState_.assign({&bodies_.poses, &bodies_.velocities, &bodies_.momenta, &bodies_.forces,
                       &bodies_.flags, &bodies_.slowFor});
    if (joints_.count > 0) stepState_.push_back(&joints_.rows);
    if (islands_) islands_->addStepState(stepState_);
    // The energy watch's lowest sum and the bodies' energies at it (a restart rewrites both).
    if (sumEnergy_ && !restartEnergy_ && energy_.lowest.bytes() > 0)
        stepState_.insert(stepState_.end(), {&energy_.atLowest, &energy_.lowest});
    aheadPairsFound_ = pairsFound_;
    aheadKeptFound_ = keptFound_;
    aheadHostWrote_ = hostWrote_;
    return stepStart_.keep(*queue_, stepState_);
}

Status Pipeline::collideSatAhead(const StepParams& params) {
    StageQueue& q = *queue_;
    Profile& profile = q.profile();
    profile.setStage(DeviceStage::BroadPhase);
    RUBBLE_TRY(broadPhase_.run(q, bodies_, shapes_, pairs_, sort_, params.dt));
    profile.setStage(DeviceStage::NarrowPhase);
    RUBBLE_TRY(collideShapes(q, bodies_, shapes_, broadPhase_.spin(), broadPhase_.boxes(), pairs_,
                             params.dt));
    RUBBLE_TRY(summarizeRound(params, 1));
    // The round's status, read with the step's end (aheadHeld).
    RUBBLE_TRY(q.keepRoundStatus());
    assumed_ = lastRound_;
    assumed_.woken = 0;
    q.assumeStatus(assumed_);
    aheadCapacity_ = pairs_.current.capacity;
    aheadRoom_ = pairs_.current.impulseRoom;
    aheadPreviousTotal_ = pairs_.previous.impulseTotal;
    pairsFound_ = assumed_.pairs;
    RUBBLE_TRY(pgs_.plan(q, pairs_, joints_, bodies_, assumed_));
    return pgs_.buildRows(q, bodies_, pairs_, params);
}

bool Pipeline::aheadHeld() const {
    // As the waiting step decides after its first round: it would have gone on, with the same
    // launches (collideSat, PgsSolve::solve).
    const DeviceStatus round = queue_->roundStatus();
    return round.pairs <= aheadCapacity_ && round.woken == 0 &&
           std::uint64_t(round.impulses) + aheadPreviousTotal_ <= aheadRoom_ &&
           round.pushes == assumed_.pushes && round.bounces == assumed_.bounces &&
           round.layers == assumed_.layers;
}

Status Pipeline::runStepAgain(const StepParams& params, const std::optional<Bodies>& readBack) {
    // Every command of the step has run: its start back in place, then the step as one that
    // waits (its profile records kept: the step's device time is both runs').
    StageQueue& q = *queue_;
    RUBBLE_TRY(stepStart_.restore(q));
    pairs_.undoKeep();
    pgs_.undoPlan();
    pairsFound_ = aheadPairsFound_;
    keptFound_ = aheadKeptFound_;
    hostWrote_ = aheadHostWrote_;
    StepInputs in;
    in.readBack = readBack;
    in.sumEnergy = sumEnergy_;
    in.restartEnergy = restartEnergy_;
    again_ = true;
    const Status s = enqueueStep(params, in);
    again_ = false;
    stepPending_ = false;
    readBack_.reset();
    RUBBLE_TRY(s);
    return q.finish();
}

Status Pipeline::collideSat(const StepParams& params) {
    if (ahead_) return collideSatAhead(params);
    StageQueue& q = *queue_;
    Profile& profile = q.profile();
    std::uint32_t woken = 0;
    for (std::uint32_t round = 1;; ++round) {
        profile.setStage(DeviceStage::BroadPhase);
        RUBBLE_TRY(broadPhase_.run(q, bodies_, shapes_, pairs_, sort_, params.dt));
        profile.setStage(DeviceStage::NarrowPhase);
        RUBBLE_TRY(collideShapes(q, bodies_, shapes_, broadPhase_.spin(), broadPhase_.boxes(), pairs_,
                                 params.dt));
        Result<DeviceStatus> st = wakeAndSummarize(params, round);
        RUBBLE_TRY(st);
        if (st->pairs > pairs_.current.capacity) {
            // Nothing has moved (the wake only woke bodies): grow and find them again.
            woken = st->woken;
            RUBBLE_TRY(growPairs(*st, params));
            continue;
        }
        Result<bool> impulsesFit = pairs_.fitImpulses(q, *st);
        RUBBLE_TRY(impulsesFit);
        if (!*impulsesFit) {
            // As after a pair overflow: the round runs again, now with room for every impulse.
            woken = st->woken;
            continue;
        }
        if (islands_) {
            // The CPU's wake ran on the device after the summaries (wakeAndSummarize): the
            // islands a restless body touches woke, and the collision runs again for their
            // pairs with sleeping bodies, until a round wakes none.
            if (st->woken == woken) break;
            woken = st->woken;
            hostWrote_ = true;
            continue;
        }
        if (st->woken == woken) break;
        // The wake reaches through the sleeping bodies that rest against the woken ones (last
        // step's entries with impulses), a round a launch, until a round wakes none; then the
        // collision runs again, as the woken bodies' pairs with sleeping ones were not found.
        woken = st->woken;
        profile.setStage(DeviceStage::Sleep);
        for (;;) {
            RUBBLE_TRY(wakeStillPairs(q, bodies_, pairs_, ++round));
            Result<DeviceStatus> spread = q.readStatus();
            RUBBLE_TRY(spread);
            if (spread->woken == woken) break;
            woken = spread->woken;
        }
    }
    pairsFound_ = q.lastStatus().pairs;
    lastRound_ = q.lastStatus();
    roundKnown_ = true;
    RUBBLE_TRY(pgs_.plan(q, pairs_, joints_, bodies_, q.lastStatus()));
    return pgs_.buildRows(q, bodies_, pairs_, params);
}

Status Pipeline::growPairs(const DeviceStatus& st, const StepParams& params) {
    // Within the step's pair budget (host/core/limits.h), as the CPU's broad phase is held to it.
    const std::size_t budget = pairBudget(bodies_.count);
    if (st.pairs > budget)
        return limitError("broadPhase", "broad-phase pairs", st.pairs, budget, params.step + 1,
                          "bodies overlap each other in large numbers");
    // An eighth more than found: the per-pair arrays are most of the device's memory, and a
    // regrowth costs one more collision of one step (12.4M pairs: 13.98M slots, not 2^24).
    const std::size_t margin = std::max<std::size_t>(st.pairs / 8, 1024);
    const auto grown = std::uint32_t(std::min<std::size_t>(st.pairs + margin, budget));
    std::fprintf(stderr,
                 "rubble: pair overflow (%u pairs, room for %u): buffers grown to %u "
                 "and the step's collision run again\n",
                 st.pairs, pairs_.current.capacity, grown);
    return pairs_.setCapacity(*queue_, grown);
}

Result<DeviceStatus> Pipeline::wakeAndSummarize(const StepParams& params, std::uint32_t round) {
    RUBBLE_TRY(summarizeRound(params, round));
    return queue_->readStatus();
}

Status Pipeline::summarizeRound(const StepParams& params, std::uint32_t round) {
    StageQueue& q = *queue_;
    // Sleeping bodies hit in this step wake before the rows, so that their mass takes part.
    q.profile().setStage(DeviceStage::Sleep);
    if (!islands_) RUBBLE_TRY(wakeTouchedPairs(q, bodies_, pairs_, joints_, round));
    q.profile().setStage(DeviceStage::BuildContactRows);
    RUBBLE_TRY(pgs_.summarize(q, bodies_, pairs_, joints_, params));
    // By islands, on this round's pairs with rows; nothing asleep at the end of the last step
    // (or since the host's upload): nothing wakes.
    if (islands_ && islands_->asleep() > 0) {
        q.profile().setStage(DeviceStage::Sleep);
        RUBBLE_TRY(islands_->wake(q, bodies_, pairs_, joints_, bodies_.movingKinematic > 0));
        q.profile().setStage(DeviceStage::BuildContactRows);
    }
    return {};
}

Status Pipeline::collideParticlePairs(const StepParams& params) {
    StageQueue& q = *queue_;
    for (;;) {
        q.profile().setStage(DeviceStage::NarrowPhase);
        RUBBLE_TRY(particles_.collide(q));
        RUBBLE_TRY(particles_.sortContacts(q, sort_, bodies_.count, true));
        RUBBLE_TRY(particles_.toPairs(q, pairs_));
        // Round 0: no wake reaches further than one contact.
        Result<DeviceStatus> st = wakeAndSummarize(params, 0);
        RUBBLE_TRY(st);
        if (st->contactsFit()) break;
        // The stages after collision saw no contacts: grow the buffers (the pairs' with them)
        // and collide again.
        RUBBLE_TRY(particles_.grow(q, *st, params.step + 1, "the step's collision"));
    }
    RUBBLE_TRY(pgs_.plan(q, pairs_, joints_, bodies_, q.lastStatus()));
    return pgs_.buildRows(q, bodies_, pairs_, params);
}

Status Pipeline::solvePairs(const StepParams& params) {
    StageQueue& q = *queue_;
    Profile& profile = q.profile();
    const float dt = params.dt;
    profile.setStage(DeviceStage::Solve);
    // The soft step moves the bodies in its substeps (SAT only: backend_check.cpp).
    if (params.solver.type == SolverType::SoftStep && sat())
        RUBBLE_TRY(softStep_.solve(q, bodies_, pgs_, pairs_, joints_, params));
    else
        RUBBLE_TRY(solvePgsPairs(params));
    stepTargets_ = {};
    RUBBLE_TRY(bodies_.clearForces(q));
    profile.setStage(DeviceStage::Sleep);
    // By islands, or each body by itself; a world kept awake does not sleep.
    if (islands_ && params.sleep)
        RUBBLE_TRY(islands_->update(q, bodies_, pairs_, joints_, dt));
    else if (params.sleep)
        RUBBLE_TRY(sleepBodies(q, bodies_, &pairs_, nullptr, joints_, dt));
    // This step's pairs, features and impulses are the next step's. With SAT, a step that found
    // no pairs after one that found none, with no body state from the host between, keeps last
    // step's set as it is: it holds still pairs only, and none of them can have moved (a moving
    // body finds the pairs of the bodies it rests against), so the carry would copy it whole.
    const bool stillSet = sat() && pairsFound_ == 0 && keptFound_ == 0 && !hostWrote_;
    keptPairs_ = !stillSet;
    if (!stillSet) {
        RUBBLE_TRY(pairs_.keep(q, bodies_, sat()));
        keptFound_ = pairsFound_;
    }
    hostWrote_ = false;
    if (sumEnergy_) RUBBLE_TRY(sumBodyEnergy(q, bodies_, energy_, params.gravity, restartEnergy_));
    return q.enqueueStatusRead();
}

Status Pipeline::solvePgsPairs(const StepParams& params) {
    StageQueue& q = *queue_;
    const float dt = params.dt;
    RUBBLE_TRY(pgs_.solve(q, bodies_, pairs_, joints_, q.lastStatus(), params));
    q.profile().setStage(DeviceStage::IntegratePositions);
    // Without a bounce nothing between the two reads the velocities applyPushes derives again.
    RUBBLE_TRY(integratePositions(q, bodies_, dt, params.symplectic(), pgs_.fusedPushes()));
    // Kinematic bodies given a target end the step on it (their velocities led there).
    RUBBLE_TRY(targets_.place(q, bodies_, stepTargets_));
    // As PgsSolver::solvePositions: bounces from the contact, the pushes, the joints.
    RUBBLE_TRY(pgs_.bounce(q, bodies_, params));
    RUBBLE_TRY(pgs_.applyPushes(q, bodies_, dt));
    return joints_.project(q, bodies_);
}

Status Pipeline::solveParticles(const StepParams& params) {
    StageQueue& q = *queue_;
    Profile& profile = q.profile();
    const float dt = params.dt;
    const SolverOptions& solver = params.solver;
    ContactBuffers& k = particles_.contacts();
    // lcp-jacobi sizes its dense problem on the host: it waits here for the contact count.
    const bool dense = solver.type == SolverType::LcpJacobi;
    profile.setStage(DeviceStage::NarrowPhase);
    RUBBLE_TRY(particles_.collide(q));
    if (dense) RUBBLE_TRY(particles_.readCount(q));
    if (deterministic_) RUBBLE_TRY(particles_.sortContacts(q, sort_, bodies_.count, false));
    // Sleeping bodies hit in this step wake before the rows, so that their mass takes part.
    profile.setStage(DeviceStage::Sleep);
    RUBBLE_TRY(wakeTouched(q, bodies_, k));
    profile.setStage(DeviceStage::BuildContactRows);
    RUBBLE_TRY(jacobi_.buildRows(q, bodies_, k, particles_.count(), params.rows, solver.warmStart));
    profile.setStage(DeviceStage::Solve);
    // lcp-jacobi solves the dense problem; the Jacobi stage then only applies its impulses.
    if (dense)
        RUBBLE_TRY(jacobi_.solveDense(q, bodies_, k, lcpStride_, solver.iterations,
                                      params.lcpJacobiRelaxation));
    RUBBLE_TRY(
        jacobi_.solve(q, bodies_, k, dense ? 0 : solver.iterations, params.jacobiRelaxation));
    profile.setStage(DeviceStage::IntegratePositions);
    RUBBLE_TRY(integratePositions(q, bodies_, dt, params.symplectic()));
    RUBBLE_TRY(bodies_.clearForces(q));
    profile.setStage(DeviceStage::Sleep);
    if (params.sleep) RUBBLE_TRY(sleepBodies(q, bodies_, nullptr, &k, joints_, dt));
    if (gatherImpulses_) RUBBLE_TRY(obstacles_.gather(q, k.rows, k.bodyStart, k.bodyList));
    // This step's contacts and impulses become the next step's warm start.
    if (solver.warmStart) RUBBLE_TRY(particles_.keepForWarmStart(q));
    if (sumEnergy_) RUBBLE_TRY(sumBodyEnergy(q, bodies_, energy_, params.gravity, restartEnergy_));
    return q.enqueueStatusRead();
}

Status Pipeline::meetStep(const StepParams& params, std::span<const std::string> names,
                          StepStats& stats) {
    RUBBLE_ASSERT(stepPending_);
    stepPending_ = false;
    StageQueue& q = *queue_;
    // The step's read-back, if it asked for one (its arrays are the caller's till we return).
    const std::optional<Bodies> readBack = std::exchange(readBack_, std::nullopt);
    const auto waitStart = std::chrono::steady_clock::now();
    RUBBLE_TRY(q.finish());
    if (ahead_ && !aheadHeld()) RUBBLE_TRY(runStepAgain(params, readBack));
    if (ahead_) {
        // The round as assumed: the step is the waiting step's. Its pairs as found.
        pairsFound_ = keptFound_ = q.roundStatus().pairs;
        lastRound_ = q.roundStatus();
    }
    stats.deviceWaitMs = msSince(waitStart);
    for (;;) {
        const DeviceStatus st = q.lastStatus();
        if (st.contactsFit()) break;
        // The stages after collision did nothing: grow the buffer and run them again.
        particles_.undoKeep();
        if (Status grown = particles_.grow(q, st, params.step + 1, "the step's contact stages");
            !grown.ok()) {
            q.profile().discard();
            return grown;
        }
        RUBBLE_TRY(solveParticles(params));
        if (readBack) RUBBLE_TRY(bodies_.enqueueRead(q, *readBack, true));
        RUBBLE_TRY(q.finish());
    }
    DeviceStatus st = q.lastStatus();
    energySummed_ = sumEnergy_;
    // The set kept holds this many impulses: the next step's carry copies at most these.
    if (pairPgs() && keptPairs_) pairs_.previous.impulseTotal = st.impulses;
    // The islands' update changed flags and velocities: the next step's pair set is kept again.
    if (islands_ && params.sleep && islands_->met(st)) hostWrote_ = true;
    if (readBack) bodies_.takeSleepFlags(*readBack);
    TrafficCounts traffic;
    countTraffic(params, st, traffic);
    ContactBuffers& k = particles_.contacts();
    k.count = st.contacts;
    if (!pairPgs() && params.solver.warmStart) k.previousCount = st.contacts;
    Result<DeviceTimes> times = q.profile().collect(traffic);
    RUBBLE_TRY(times);
    stats.deviceMs = times->busyMs;
    stats.deviceStages = times->stages;
    stats.deviceContactCount = st.contacts;
    stats.deviceAsleep = st.asleep;
    stats.asleep = st.asleep;
    // Besides the wait at the step's end.
    stats.deviceWaits = std::uint32_t(q.waits() - waitsAtBegin_ - 1);
    stats.largestPenetration = std::max(stats.largestPenetration, st.largestPenetration);
    stats.solverResidual = std::max(stats.solverResidual, st.solverResidual);
    if (st.firstNonFinite < bodies_.count)
        return makeError(
            ErrorKind::Numerical, "body " + names[st.firstNonFinite],
            "its state is not finite after step " + std::to_string(params.step + 1) +
                " (t = " + std::to_string(double(params.step + 1) * double(params.dt)) + " s)");
    return {};
}

void Pipeline::countTraffic(const StepParams& params, const DeviceStatus& st,
                            TrafficCounts& t) const {
    const WorkSizes& sizes = queue_->c().workSizes();
    const ContactBuffers& k = particles_.contacts();
    t.bodies = bodies_.count;
    t.particles = particles_.count();
    t.cells = std::uint64_t(1) << particles_.cellBits();
    t.contacts = st.contacts;
    t.previous = params.solver.warmStart ? k.previousCount : 0u;
    t.sortItems = sizes.sortItems;
    t.jointReal = sizes.jointRealBytes();
    if (!pairPgs()) return;
    t.pairs = st.pairs;
    t.gridEntries = st.gridEntries;
    t.largeBodies = st.largeBodies;
    t.planes = broadPhase_.planeCount();
    t.kept = st.kept;
    t.carried = st.carried;
    t.joints = joints_.count;
    t.jointBodies = joints_.bodyCount;
    t.directGroups = joints_.directGroupCount;
    t.directMembers = joints_.directMemberCount;
    t.directRows = joints_.directRowCount;
    t.directMatrix = joints_.directMatrixCount;
}

} // namespace rubble::gpu
