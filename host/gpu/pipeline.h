// host/gpu/pipeline.h: the OpenCL pipeline of one world (DESIGN.md, "One step, OpenCL
// pipeline"): the device stages of the world's collision method and solver, made once, and the
// device step as the list of their calls (host/gpu/device_step.cpp). A step is enqueued whole
// without waiting (beginStep) and met once (endStep), so that the host can step its own bodies
// meanwhile. Each stage lives in host/gpu/<stage>.{h,cpp} and can be built and run alone.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "host/core/step_params.h"
#include "host/gpu/broad_phase.h"
#include "host/gpu/forces.h"
#include "host/gpu/integrate.h"
#include "host/gpu/jacobi.h"
#include "host/gpu/joints.h"
#include "host/gpu/pairs.h"
#include "host/gpu/particles.h"
#include "host/gpu/pgs.h"
#include "host/gpu/pipeline_handle.h"
#include "host/gpu/sat.h"
#include "host/gpu/sleep.h"
#include "host/gpu/soft_step.h"
#include "host/gpu/sort.h"
#include "host/gpu/step_start.h"
#include "rubble/world.h"

namespace rubble::gpu {

/// What a pipeline is made from: the bodies (uploaded at creation, kept on the device), their
/// particles and surfaces, and which of them the host steps.
struct PipelineInput {
    BodiesView bodies;                        ///< poses, velocities, momenta, forces, masses
    const ParticleSet* particles = nullptr;   ///< null: none
    std::span<const shared::float4> surfaces; ///< per body: friction, restitution
    /// Per body, or empty: the host steps it (debris offloading); it is an infinite mass on the
    /// device, placed by each step's obstacles, whose list is these bodies' indices in order.
    std::span<const std::uint8_t> kinematic;
    bool deterministic = false; ///< contacts sorted by key so that atomics cannot reorder sums
    int pgsBlocks = -1;         ///< RunOptions::pgsBlocks
    PgsColoring pgsColoring = PgsColoring::Host; ///< RunOptions::pgsColoring, resolved
    /// The world's collision method: with Sat the shapes' hulls go to the device (and `shapes`
    /// must hold every shape the bodies use); with Particles the particles do.
    CollisionMethod collision = CollisionMethod::Particles;
    std::span<const Shape> shapes;    ///< indexed by bodies.shapeOf
    std::span<const BodyPair> joined; ///< joined bodies (min, max), sorted: they do not collide
    std::span<const shared::PgsJoint> joints; ///< SAT: the joints, in body frames
    /// Particles: their contacts solved by projected Gauss-Seidel (each contact a pair of one
    /// point) instead of the Jacobi family.
    bool particlePgs = false;
    /// Particles: the first guess of the contacts the buffers hold (0: a few per particle);
    /// a step that finds more grows them.
    std::uint32_t contactCapacity = 0;
    /// SAT: the first guess of the pairs the buffers hold (0: four per body, at least 1024); a
    /// step that finds more grows them.
    std::uint32_t pairCapacity = 0;
    /// SAT: bodies sleep by the CPU's islands, on the device (DeviceIslands); false, each body
    /// sleeps by itself (RunOptions::bodySleep).
    bool islands = false;
};

/// What a step takes from the host besides its parameters.
struct StepInputs {
    std::span<const EventDesc> explosions;            ///< due this step
    std::span<const shared::ObstacleState> obstacles; ///< one per obstacle, in obstacle order
    bool gatherObstacleImpulses = false;              ///< two-way coupling
    /// Poses the scene's kinematic bodies end this step on (SAT), each with its body's index,
    /// velocity and device flags; they must stay put until endStep.
    std::span<const shared::ObstacleState> kinematicTargets;
    /// Velocities the host gave the scene's kinematic bodies since the last step, each with its
    /// body's index and device flags (the pose is not read); they must stay put until endStep.
    std::span<const shared::ObstacleState> kinematicVelocities;
    /// When set, the step ends by reading every body back into these arrays (as downloadBodies
    /// does), in the same queue as the step, so that the host waits once: they must stay put
    /// until endStep.
    std::optional<Bodies> readBack;
    /// When set, the step ends by summing the bodies' energy into its status block
    /// (energyOfLastStep), for the host's blow-up watch without reading the bodies.
    bool sumEnergy = false;
    /// With sumEnergy: this step is the watch's new reference (its energies the lowest so far).
    bool restartEnergy = false;
};

class Pipeline {
  public:
    /// Makes the stages of the world's method and uploads its bodies (and particles or hulls).
    /// Errors: NotSupported past RUBBLE_TAG_MAX_BODIES bodies or for a hull the device cannot
    /// clip, Device.
    static Result<PipelineHandle> create(std::shared_ptr<Context> context, const PipelineInput& in);

    const Context& context() const { return queue_->c(); }
    const std::shared_ptr<Context>& sharedContext() const { return queue_->sharedContext(); }

    /// Copies the host's poses, velocities, momenta, masses and flags to the device: at load,
    /// and when the host changed them (impulses). Errors: Device.
    Status uploadBodies(BodiesView bodies);
    /// This step's forces and torques (World::addForce), uploaded when any were added.
    Status uploadForces(std::span<const shared::BodyForce> forces);
    /// Reads poses, velocities, momenta and the sleep flags back into the host arrays.
    /// Errors: Device.
    Status downloadBodies(Bodies bodies);
    /// The bodies' energy and its rounding scale (DeviceStatus::energy, energyScale) as the step
    /// met last summed them, if it did (StepInputs::sumEnergy).
    std::optional<std::pair<float, float>> energyOfLastStep() const;
    /// Each body's energy (J) when the device's sum was the lowest since the watch's last
    /// reference (StepInputs::restartEnergy), read into `out` (one per body). Errors: Device.
    Status downloadLowestEnergies(std::vector<double>& out);
    /// How many times the bodies were read back so far (downloadBodies, StepInputs::readBack).
    std::uint64_t bodyReads() const { return bodyReads_; }
    /// Reads `count` BodyPose records from body `first` on into `out`, for drawing.
    /// Errors: Device.
    Status downloadPoses(std::uint32_t first, std::uint32_t count, void* out);

    /// Enqueues a whole step without waiting (host/gpu/device_step.cpp). SAT waits once in the
    /// middle, for the status after the summaries, unless the step runs ahead (no blocks, the
    /// device's plan, nothing from the host); lcp-jacobi waits for its dense problem's size.
    /// Errors: Device, Limit.
    Status beginStep(const StepParams& params, const StepInputs& in);
    /// Waits for the step, reads its status and device times into `stats`. On a contact
    /// overflow the buffers grow and the stages from collision on run again (said on stderr); a
    /// step that ran ahead on what its status turned out not to be runs again from its start.
    /// Errors: Device, Limit, Numerical (a body that is not finite, named by `names`).
    Status endStep(const StepParams& params, std::span<const std::string> names, StepStats& stats);
    /// Whether the last step left the world at rest, so that the next one would change nothing
    /// on the device: SAT with islands, every moving body asleep, no pair found in
    /// it or in the kept set's step, no obstacles, and nothing uploaded since. The caller may
    /// then leave the step out unless it has something for the device (an explosion).
    bool atRest() const;
    /// The bodies asleep by the islands after the last step.
    std::uint32_t asleepBodies() const { return islands_ ? islands_->asleep() : 0; }
    /// The impulses the rows put on each obstacle in the step met last (two-way coupling).
    std::span<const shared::BodyImpulse> obstacleImpulses() const { return obstacles_.impulses(); }

    /// Device time of each kernel and transfer over the steps so far.
    std::vector<CommandTotals> profileTotals() const { return queue_->profile().totals(); }
    /// Whether the steps keep each command's times for lastCommands() (rubble run --trace).
    void keepCommands(bool keep) { queue_->profile().keepCommands(keep); }
    std::span<const DeviceCommand> lastCommands() const { return queue_->profile().lastCommands(); }
    /// Carries another pipeline's totals on (a world's device arrays built again).
    void keepProfileOf(const Pipeline& old) { queue_->profile().addTotals(old.queue_->profile()); }

  private:
    Pipeline() = default;
    /// The stages of the world's method, its bodies uploaded. Errors: those of create.
    Status makeStages(const PipelineInput& in);
    bool sat() const { return method_ == CollisionMethod::Sat; }
    bool pairPgs() const { return sat() || particlePgs_; }
    // The device step's parts (host/gpu/device_step.cpp).
    Status enqueueStep(const StepParams& params, const StepInputs& in);
    Status meetStep(const StepParams& params, std::span<const std::string> names, StepStats& stats);
    Status collideSat(const StepParams& params);
    Status collideParticlePairs(const StepParams& params);
    Status solvePairs(const StepParams& params);
    Status solvePgsPairs(const StepParams& params);
    Status solveParticles(const StepParams& params);
    Result<DeviceStatus> wakeAndSummarize(const StepParams& params, std::uint32_t round);
    Status growPairs(const DeviceStatus& st, const StepParams& params);
    // A step run ahead (device_step.cpp): whether this one may, its start kept, its round
    // checked once met, and run again from its start when the check fails.
    bool mayRunAhead(const StepInputs& in) const;
    Status keepStepStart();
    Status collideSatAhead(const StepParams& params);
    Status summarizeRound(const StepParams& params, std::uint32_t round);
    bool aheadHeld() const;
    Status runStepAgain(const StepParams& params, const std::optional<Bodies>& readBack);
    void countTraffic(const StepParams& params, const DeviceStatus& st, TrafficCounts& t) const;

    std::unique_ptr<StageQueue> queue_;
    DeviceBodies bodies_;
    RadixSort sort_;
    ObstacleCoupling obstacles_;
    KinematicTargets targets_;
    std::span<const shared::ObstacleState> stepTargets_; ///< this step's kinematic targets
    ParticleCollision particles_;
    PairStore pairs_;
    DeviceShapes shapes_;
    SatBroadPhase broadPhase_;
    DeviceJoints joints_;
    PgsSolve pgs_;
    SoftStepSolve softStep_; ///< SAT with the soft step: its substeps over pgs_'s plan and rows
    JacobiSolve jacobi_;
    std::unique_ptr<DeviceIslands> islands_; ///< SAT sleeping by islands
    CollisionMethod method_ = CollisionMethod::Particles;
    bool particlePgs_ = false;
    bool deterministic_ = false;
    std::uint32_t lcpStride_ = 1; ///< rows per contact of lcp-jacobi (lcpStride)
    // The step in flight and what the next step may skip.
    bool stepPending_ = false;
    std::optional<Bodies> readBack_;
    bool sumEnergy_ = false;     ///< the step in flight sums the bodies' energy
    bool restartEnergy_ = false; ///< and starts the watch's reference again
    EnergyBuffers energy_;
    bool energySummed_ = false; ///< the step met last did
    std::uint64_t bodyReads_ = 0;
    bool gatherImpulses_ = false;
    /// SAT: the pairs this step's collision found, and those of the set kept as last step's;
    /// whether the host wrote body state since the last step.
    std::uint32_t pairsFound_ = 0, keptFound_ = 0;
    bool hostWrote_ = false;
    bool uploaded_ = false; ///< the host uploaded the bodies since the last step began
    /// This step's pair set became last step's (PairStore::keep ran): the status read at the
    /// step's end holds the impulse slots it took.
    bool keptPairs_ = false;
    /// SAT: the status after the last collision round of the step met last (roundKnown_: one
    /// was), which a step run ahead assumes of its own round.
    DeviceStatus lastRound_;
    bool roundKnown_ = false;
    /// This step runs ahead: it did not wait for its round's status, assumed `assumed_` (with
    /// the pair and impulse room and the previous set's impulses as they were) and keeps its
    /// start in stepStart_ (the buffers of stepState_).
    bool ahead_ = false;
    bool again_ = false; ///< the step is running again after a failed run ahead
    DeviceStatus assumed_;
    std::uint32_t aheadCapacity_ = 0, aheadRoom_ = 0, aheadPreviousTotal_ = 0;
    std::uint32_t aheadPairsFound_ = 0, aheadKeptFound_ = 0;
    bool aheadHostWrote_ = false;
    StepStart stepStart_;
    std::vector<const Buffer*> stepState_;
    /// The queue's waits (blocking transfers, finishes) when the step began.
    std::uint64_t waitsAtBegin_ = 0;
};

} // namespace rubble::gpu
