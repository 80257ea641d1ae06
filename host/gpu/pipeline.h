// host/gpu/pipeline.h: the OpenCL pipeline of one world (DESIGN.md, "One step, OpenCL
// pipeline"): the device arrays, uploaded at load and kept there, and one method per stage.
// Each stage's dispatch lives in host/gpu/<stage>.cpp; its CPU twin has the same name. A step
// is enqueued whole without waiting (beginStep) and met once (endStep), so that the host can
// step its own bodies meanwhile.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "host/collision/contact.h"
#include "host/collision/particles.h"
#include "host/core/bodies.h"
#include "host/core/step_params.h"
#include "host/geometry/shape.h"
#include "host/gpu/buffer.h"
#include "host/gpu/coloring.h"
#include "host/gpu/context.h"
#include "host/gpu/lcp_jacobi.h"
#include "host/gpu/pipeline_handle.h"
#include "host/gpu/profile.h"
#include "rubble/scene.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/contact_row.h"
#include "rubble/shared/hull_contact.h"
#include "rubble/shared/obstacle.h"
#include "rubble/shared/pgs_joint.h"
#include "rubble/world.h"

namespace rubble::gpu {

/// The body arrays on the device, one element per body in world order.
struct BodyBuffers {
    std::uint32_t count = 0;
    Buffer poses, velocities, momenta, forces, masses;
    Buffer flags;    ///< RUBBLE_BODY_* per body: the device's own (sleep, kinematic)
    Buffer slowFor;  ///< per body: how long it has been slow, s (sleeping)
    Buffer restless; ///< per body: RUBBLE_RESTLESS_* bits of this step's contacts
    Buffer atStart;  ///< velocities before the step's forces (restitution, explicit Euler)
    Buffer before;   ///< velocities before the solve
    Buffer jacobi;   ///< JacobiBody per body, this step's
};

/// The particles and the grid over them.
struct ParticleBuffers {
    std::uint32_t count = 0, staticCount = 0, bits = 0;
    float cellSize = 0; ///< m
    float margin = 0;   ///< m: ParticleSet::margin
    Buffer records, statics, world;
    Buffer keys, values, keysAlt, valuesAlt; ///< sorted cell keys and particles (ping-pong)
    Buffer histogram, offsets;               ///< radix sort counts and their exclusive scan
    Buffer cellFirst; ///< per cell and one more: the first sorted slot of a key >= the cell's
    Buffer sortedWorld, sortedTags; ///< positions and bodyTagItem in sorted order, for collision
};

/// Contacts, rows, the per-body row lists, and last step's contacts for warm starting. The
/// contact count is known on the device; the host learns it when the step is met.
struct ContactBuffers {
    std::uint32_t capacity = 0;
    std::uint32_t count = 0;         ///< contacts of the last step met (or uploaded)
    std::uint32_t previousCount = 0; ///< contacts in `previous`, for warm starting
    bool growable = true; ///< grow on overflow (tests turn it off to see the error)
    Buffer contacts, previous, unsorted;
    Buffer rows, previousRows;
    Buffer impulses; ///< per row: its impulse on body b this sweep (rowImpulseItem)
    Buffer bodyCount, bodyStart, cursor, bodyList;
    Buffer arms;     ///< per list entry: the contact point from the body's centre of mass
    Buffer head, next; ///< last step's contacts chained per particle
    Buffer surfaces;   ///< per body: friction, restitution
    Buffer sortKeys, sortValues, sortKeysAlt, sortValuesAlt;
};

/// The host's bodies on the device (debris offloading): kinematic there, placed every step, and
/// the impulses the device's rows put on them.
struct ObstacleBuffers {
    std::uint32_t count = 0;
    Buffer states;   ///< ObstacleState per obstacle, this step's
    Buffer bodies;   ///< their body indices
    Buffer impulses; ///< BodyImpulse per obstacle, gathered after the solve
};

/// One step's body pairs of the SAT method with what each keeps for the next step: this step's
/// set and last step's swap at the end of a step (Pipeline::keepPairFeatures).
struct PairSet {
    std::uint32_t capacity = 0; ///< pairs the buffers hold
    /// BodyPairRecord: the step's pairs sorted by (a, b), then (SAT, from the end of the step)
    /// the still pairs carried from the step before (markStillPairs), sorted among themselves.
    Buffer pairs;
    /// Two uints: the pairs found (may exceed capacity), and the entries kept for the next
    /// step's lookups (keptPairsItem: the pairs found and the still pairs carried after them;
    /// 0 in a set that carries nothing, the particles').
    Buffer count;
    Buffer features; ///< PairCache per pair, in pair order
    /// PGS: each pair's contact impulses at the end of its step (4 PgsImpulse slots per pair),
    /// and how many of its slots hold one; the next step's rows warm-start from them.
    Buffer impulses, impulseCount;
    /// Particles with PGS: each pair's ParticleContactKey (a pair is one contact), in pair order.
    Buffer keys;
};

/// The SAT collision method on the device, made only for a world that collides with SAT: the
/// shapes' hulls (host/gpu/hull_data.h), per-body boxes and flags, the broad phase's columns,
/// the pairs, and the manifolds (ContactManifold, one per pair in pair order; count 0: no contact).
struct SatBuffers {
    bool enabled = false;
    std::uint32_t planeCount = 0, joinedCount = 0;
    std::uint32_t gridBits = 0;  ///< the columns' keys are below 2^gridBits
    std::uint32_t sweepBits = 0; ///< the sweep keys' bits, below the column's in an entry's key
    // Hulls, once per world.
    Buffer shapes, shapeOf, vertices, vertexEdges, neighbourStart, neighbours, halfEdges, faces,
        faceEdges, edges;
    Buffer planes; ///< indices of the plane bodies
    Buffer joined; ///< joined body pairs (min, max), sorted: they do not collide
    // Per body, each step.
    Buffer boxes;      ///< BodyBox (a plane body: its world plane in min)
    Buffer spin;       ///< the part of the reach due to turning, m
    Buffer broadFlags; ///< RUBBLE_BROAD_*
    // The grid.
    Buffer partials, grid;
    Buffer keys, values, keysAlt, valuesAlt; ///< (cell, body) entries, 8 per body at most
    Buffer cellBoxes;                        ///< each sorted entry's box
    Buffer large;                            ///< bodies too large for the grid
    // Pairs: found in any order, then sorted into current.pairs.
    Buffer found, bodyCount, bodyStart, cursor;
    PairSet current, previous;
    Buffer manifolds; ///< ContactManifold per pair of `current`, in pair order
    /// Per pair of `current`: its index among last step's entries (collideShapes), their count
    /// when it is new; summarizePairs and buildPgsRows read it.
    Buffer previousOf;
    /// The still pairs' carry at the end of a step (keepPairFeatures): per entry of last step's
    /// set whether it is carried and its place among the carried; per chunk of the set (the
    /// sort's work-items) the count and its scan.
    Buffer carry, place, chunkCounts, chunkStarts;
};

/// One launch of the device's sweeps over the elements [first, first + count) of the step's
/// order, by `mode` (RUBBLE_PGS_*): a color's, one per work-item; the last colors together on
/// one work-item (serial); or the blocks, one work-group each.
struct PgsLaunch {
    cl_uint first = 0, count = 0, mode = RUBBLE_PGS_PER_ITEM;
    std::uint32_t points = 0; ///< rows, for the byte counts
    std::uint32_t blocks = 0; ///< RUBBLE_PGS_BLOCKS: how many (PgsBuffers::blockStarts)
    /// Work-items of the launch in groups of `group`.
    std::size_t items(std::size_t group) const {
        if (mode == RUBBLE_PGS_BLOCKS) return std::size_t(blocks) * group;
        return mode == RUBBLE_PGS_SERIAL ? group : count;
    }
};

/// Projected Gauss-Seidel on the device (host/gpu/pgs.cpp, kernels/pgs.cl), for a world that
/// collides with SAT: the rows of this step's pairs (4 slots per pair), the coloring's order,
/// and the split position pass's per-body state.
struct PgsBuffers {
    Buffer pairRows;       ///< per pair: its point count and RUBBLE_PGS_MOVES_* (0: no rows)
    Buffer elements;       ///< this step's PgsElement records, block by block, then by color
    Buffer buildOrder;     ///< the pairs' elements (indices into elements) in pair order
    /// The blocks' first elements and the end of the last, then each block's passes over its
    /// elements' points (solvePgs, pushPgs, bouncePgs)
    Buffer blockStarts;
    Buffer normalRows;     ///< PgsNormalRow per point, packed in element order
    Buffer frictionRows;   ///< PgsFrictionRows per point, in the same order
    Buffer impulses;       ///< per point: normal, two friction and push impulses, N s
    Buffer pushed;         ///< per body: a pushing row moves it
    Buffer push;           ///< per body: the push velocities (BodyVelocity)
    Buffer sweepResidual;  ///< per push sweep: the largest change, float bits
    Buffer bounce;         ///< per point: the restitution pass's impulse, N s
    /// Per body: the velocities the sweeps left, on which the restitution pass sweeps (as the
    /// CPU's on its solver's velocities, not on those integratePositions derives again).
    Buffer solved;
    Buffer bounceResidual; ///< per restitution sweep: the largest change, float bits
    bool bounces = false;  ///< this step: a row may bounce (the non-fused path runs)
    bool pushes = false;   ///< this step: the split position pass ran (applyPushes moves)
    /// The split pass's sweeps run in the velocity sweeps' launches and applyPushes follows
    /// integratePositions directly (a row pushed, none bounces).
    bool fusedPushes() const { return pushes && !bounces; }
    // The layer pass's scratch (layerPgs): per body its layer and marks, the rows' lists, the
    // histogram of lower layers.
    Buffer layer, loaded, layerRows, layerSorted, layerHistogram;
    std::uint32_t rowCount = 0; ///< points with rows this step
    // Joints: in body frames (once per world), their rows and impulses (kept between steps),
    // the jointed bodies, and the joints colored once over the dynamic bodies for the position
    // projection.
    std::uint32_t jointCount = 0, jointBodyCount = 0, jointGroupCount = 0;
    Buffer joints, jointRows, jointBodies, jointOrder, jointMoved;
    Buffer jointGroupOf; ///< per jointed body: its joint group (RUBBLE_NO_GROUP: not dynamic)
    Buffer groupVotes;   ///< per joint group: a member stays awake (1), a member is awake (2)
    // The position projection: joint groups of at most RUBBLE_JOINT_DIRECT_ROWS rows solved
    // as one (JointGroup records, their members, and their scratch), the joints of larger
    // groups joint by joint over jointColoring (jointOrder).
    std::uint32_t directGroupCount = 0;
    /// Totals over the directly projected groups: members, rows, and floats of their matrices
    /// (for the byte counts, host/gpu/traffic.cpp).
    std::uint32_t directMemberCount = 0, directRowCount = 0, directMatrixCount = 0;
    Buffer directGroups, groupMembers, positionRows, positionMatrix, positionSolution;
    Buffer deltaPosition, deltaRotation; ///< per body, zero between uses
    std::vector<shared::PgsJoint> jointsHost;
    std::vector<std::uint8_t> jointDynamicA, jointDynamicB;
    Coloring jointColoring;
    Coloring coloring;
    std::vector<ColorElement> stepElements;    ///< the joints, then the pairs with rows
    std::vector<ColorElement> coloredPairs;    ///< the pairs with rows between blocks
    std::vector<std::uint32_t> coloredHost;    ///< the elements between blocks (indices)
    std::vector<std::uint32_t> placeHost;      ///< each element's place in elementsHost
    std::vector<std::uint32_t> blockOfHost;    ///< each element's block, or all ones: colored
    std::vector<std::uint32_t> blockStartsHost, nextHost, pointsHost;
    /// This round's pairs and their summaries on the host (readPairSummaries), read once
    /// after summarizePairs for the host's wake and the coloring alike.
    std::vector<cl_uint> pairRowsHost;
    std::vector<shared::BodyPairRecord> pairsHost;
    bool summariesOnHost = false; ///< pairsHost and pairRowsHost hold this round's
    std::vector<shared::PgsElement> elementsHost;
    std::vector<PgsLaunch> launches;        ///< this step's launches of each sweep
};

/// What a host-side sleep decision did (HostSleep::update).
struct HostSleepCounts {
    std::uint32_t asleep = 0;     ///< bodies asleep after it
    std::uint32_t fellAsleep = 0; ///< bodies it put to sleep (their velocities and momenta zeroed)
    std::uint32_t woken = 0;      ///< bodies it woke
};

/// Sleep decided on the host for a world that collides with SAT (host/gpu/sleep.cpp): the
/// pipeline hands it the step's pairs with rows, which it reads for the coloring anyway, and
/// the bodies' state, and writes the flags (and the stopped bodies) it gets back to the device.
/// host/world implements it with the CPU's islands (host/dynamics/islands.h), so that the device
/// sleeps and wakes as the CPU does; host/gpu does not include host/dynamics.
class HostSleep {
  public:
    virtual ~HostSleep() = default;
    /// After a collision round, when a body is asleep: wakes what this round's contacts
    /// (`touching`) and the joints join to a restless body, on `approach` (the velocities before
    /// the forces), by clearing RUBBLE_BODY_ASLEEP in `masses`. Returns the bodies it woke.
    virtual std::uint32_t wake(std::span<const BodyPair> touching,
                               std::span<shared::BodyMass> masses,
                               std::span<const shared::BodyVelocity> approach) = 0;
    /// Once the step has run: each body's sleep on the step's velocities; a body put to sleep
    /// has RUBBLE_BODY_ASLEEP set in `masses` and its velocities and momenta zeroed.
    virtual HostSleepCounts update(std::span<const BodyPair> touching,
                                   std::span<shared::BodyMass> masses,
                                   std::span<shared::BodyVelocity> velocities,
                                   std::span<shared::BodyMomentum> momenta, float dt) = 0;
};

/// The pipeline's side of a HostSleep: the host's copy of the masses and flags, and the arrays
/// it reads from the device.
struct HostIslands {
    std::shared_ptr<HostSleep> sleep; ///< null: each body sleeps by itself on the device
    /// Per body: the device's masses (kinematic bodies as walls), flags as the host last set or
    /// read them on the device.
    std::vector<shared::BodyMass> masses;
    std::vector<BodyPair> touching; ///< this round's pairs with rows
    std::uint32_t asleep = 0;       ///< bodies asleep after the last update
    /// This step's flags (an explosion on the device wakes bodies) and velocities before the
    /// forces are on the host: read in the step's first round that wakes, kept for later rounds.
    bool stepRead = false;
    // Host copies read from the device (the update without a step's read-back).
    std::vector<cl_uint> flags;
    std::vector<shared::BodyVelocity> approach, velocities;
    std::vector<shared::BodyMomentum> momenta;
    bool enabled() const { return sleep != nullptr; }
};

/// What the host reads at the end of a step (RUBBLE_STATUS_* slots).
struct DeviceStatus {
    std::uint32_t contacts = 0;
    std::uint32_t firstNonFinite = 0xffffffffu; ///< a body index, or none
    float largestPenetration = 0;               ///< m
    float solverResidual = 0;                   ///< N s
    std::uint32_t capacity = 0;
    std::uint32_t asleep = 0, woken = 0;
    std::uint32_t pairs = 0; ///< SAT: body pairs the broad phase found (may exceed the room)
    std::uint32_t gridEntries = 0, largeBodies = 0; ///< SAT: the broad phase's grid
    /// SAT: last step's kept pair entries (its pairs and the still pairs it carried), as
    /// markStillPairs saw them, and the still pairs carried into this step's set; both 0 when
    /// the carry did not run. wakeStillPairs reads the same entries and runs only in steps that
    /// find pairs, whose carry runs.
    std::uint32_t kept = 0, carried = 0;
};

/// What a pipeline is made from: the bodies (uploaded at creation, kept on the device), their
/// particles and surfaces, and which of them the host steps.
struct PipelineInput {
    BodiesView bodies;                        ///< poses, velocities, momenta, forces, masses
    const ParticleSet* particles = nullptr;   ///< null: none (contacts are uploaded by hand)
    std::span<const shared::float4> surfaces; ///< per body: friction, restitution
    /// Per body, or empty: the host steps it (debris offloading); it is an infinite mass on the
    /// device, placed by each step's obstacles, whose list is these bodies' indices in order.
    std::span<const std::uint8_t> kinematic;
    bool deterministic = false; ///< contacts sorted by key so that atomics cannot reorder sums
    int pgsBlocks = -1;         ///< RunOptions::pgsBlocks
    /// The world's collision method: with Sat the SAT buffers are made (and `shapes` must hold
    /// every shape the bodies use); with Particles nothing of SAT is.
    CollisionMethod collision = CollisionMethod::Particles;
    std::span<const Shape> shapes;    ///< indexed by bodies.shapeOf
    std::span<const BodyPair> joined; ///< joined bodies (min, max), sorted: they do not collide
    std::span<const shared::PgsJoint> joints; ///< SAT: the joints, in body frames
    /// Particles: their contacts solved by projected Gauss-Seidel (each contact a pair of one
    /// point, particlePairs) instead of the Jacobi family.
    bool particlePgs = false;
    /// SAT: the sleep decided on the host (the world's islands); null, each body sleeps by
    /// itself on the device (kernels/sleep.cl, as the particle paths do; RunOptions::bodySleep).
    std::shared_ptr<HostSleep> hostSleep;
};

/// What a step takes from the host besides its parameters.
struct StepInputs {
    std::span<const EventDesc> explosions;           ///< due this step
    std::span<const shared::ObstacleState> obstacles; ///< one per obstacle, in obstacle order
    bool gatherObstacleImpulses = false;              ///< two-way coupling
    /// When set, the step ends by reading every body back into these arrays (as downloadBodies
    /// does), in the same queue as the step, so that the host waits once: they must stay put
    /// until endStep.
    std::optional<Bodies> readBack;
};

class Pipeline {
  public:
    /// Sizes the device arrays for a world and uploads its bodies and particles.
    /// Errors: NotSupported past RUBBLE_TAG_MAX_BODIES bodies, Device.
    static Result<PipelineHandle> create(std::shared_ptr<Context> context,
                                         const PipelineInput& in);

    const Context& context() const { return *context_; }
    const std::shared_ptr<Context>& sharedContext() const { return context_; }
    const BodyBuffers& bodies() const { return bodies_; }

    /// Copies the host's poses, velocities, momenta, masses and flags to the device: at load,
    /// and when the host changed them (impulses). Errors: Device.
    Status uploadBodies(BodiesView bodies);
    /// Reads poses, velocities, momenta and the sleep flags back into the host arrays, for
    /// whoever asked for the state (World::body, writers, metrics). Errors: Device.
    Status downloadBodies(Bodies bodies);
    /// Enqueues downloadBodies' reads without waiting; takeSleepFlags then merges the flags, once
    /// the queue has run them. `profile` (optional) times them. Errors: Device.
    Status enqueueBodyRead(Bodies bodies, Profile* profile);
    void takeSleepFlags(Bodies bodies) const;
    /// Reads `count` BodyPose records from body `first` on into `out` (as many bytes), for
    /// drawing. Errors: Device.
    Status downloadPoses(std::uint32_t first, std::uint32_t count, void* out);
    /// This step's forces and torques (World::addForce), uploaded when any were added.
    Status uploadForces(std::span<const shared::BodyForce> forces);

    /// Enqueues a whole step without waiting: the obstacles placed, the explosions, every
    /// stage, and the read of the status block (and of the obstacles' impulses). Only
    /// lcp-jacobi waits in the middle (its dense problem is sized on the host). Errors: Device.
    Status beginStep(const StepParams& params, const StepInputs& in);
    /// Waits for the step, reads its status and device times into `stats`. On a contact
    /// overflow the buffer grows and the stages from collision on run again (said on stderr),
    /// or, when it may not grow, an error. Errors: Device, Numerical (a contact overflow, a body
    /// that is not finite, named).
    /// `names` (per body) name a body that is not finite.
    Status endStep(const StepParams& params, std::span<const std::string> names,
                   StepStats& stats);
    /// Whether the last step left the world at rest, so that the next one would change nothing
    /// on the device but its status block: SAT with the CPU's islands on the host, every moving
    /// body asleep, no pair found and none in the kept set's last find (the next step would keep
    /// the set as it is, enqueueSatSolve), no obstacles, and nothing uploaded or added since.
    /// The caller may then leave the step out, unless it has something for the device (an
    /// explosion); the step's asleep count is asleepBodies().
    bool atRest() const {
        return sat_.enabled && islands_.enabled() && !stepPending_ && pairsFound_ == 0 &&
               keptFound_ == 0 && islands_.asleep == movingBodies_ && !hostBodies_ &&
               !forcesOnDevice_ && obstacles_.count == 0;
    }
    /// The bodies asleep by the host's islands after the last step.
    std::uint32_t asleepBodies() const { return islands_.asleep; }
    /// The impulses the rows put on each obstacle in the step met last (two-way coupling).
    std::span<const shared::BodyImpulse> obstacleImpulses() const { return impulsesHost_; }

    // Stages, each the twin of the CPU function of the same name. They only enqueue.
    Status integrateVelocities(shared::float4 gravity, float dt);
    Status absorbVelocityChange();
    /// `pushesFollow`: applyPushes comes next and derives the velocities of the bodies that moved
    /// in the solve (PGS on the device, a row pushed, none bounces), so this leaves theirs.
    Status integratePositions(float dt, bool symplectic, bool pushesFollow = false);
    /// Copies the velocities into `to` (atStart or before).
    Status copyVelocities(Buffer& to);
    Status transformParticles();
    /// Cell keys, the radix sort, the cell ranges and the sorted copies of the particles.
    Status buildGrid();
    /// Contacts into the contact buffer, counted in the status block.
    Status collideParticles();
    /// Waits for the queue and reads the contact count into contacts().count; an overflow grows
    /// the buffer and collides again, or is an error when the buffer may not grow. Errors:
    /// Device, Numerical.
    Status readContactCount();
    /// Deterministic mode: contacts ordered by a stable sort on their particle; `byPair` (PGS)
    /// then by their pair (lower, higher body), the CPU's order of its manifolds.
    Status sortContacts(bool byPair = false);
    /// Particles with PGS, after sortContacts(true): each contact a pair of one point in the
    /// pair arrays (kernels/particles.cl, particlePairs), last step's same contact found by key.
    Status particlePairs();
    /// What each body is to the rows (jacobiBodies): its inverse mass and world inverse
    /// inertia, zero for a body that does not move (static, asleep, kinematic).
    Status prepareJacobiBodies();
    /// Row lists per body, warm start, rows.
    Status buildJacobiRows(const shared::SolverParams& params, bool warmStart);
    /// Copies the velocities to `before`, then `iterations` sweeps (rows, then the gather); with
    /// warmStart, keeps this step's contacts and rows for the next step's warm start.
    Status solveJacobi(int iterations, float relaxation, bool warmStart);
    /// lcp-jacobi: the dense problem from the rows (`stride` rows per contact), `iterations`
    /// sweeps, the impulses back into the rows; solveJacobi(0, ...) then applies them.
    Status solveLcpJacobi(std::uint32_t stride, int iterations, float relaxation);
    /// Explosions on the device's bodies (stage applyForces).
    Status applyExplosion(const EventDesc& e);
    /// The obstacles' states for this step (stage applyForces).
    Status placeObstacles(std::span<const shared::ObstacleState> obstacles);
    /// Stage wakeTouched: the sleeping bodies that this step's contacts touch with a waking body
    /// wake before the rows (kernels/sleep.cl).
    Status wakeTouched();
    /// Stage wake for SAT, after the narrow phase: the sleeping bodies that a pair with points
    /// joins to a waking body wake (kernels/sleep.cl, wakeTouchedPairs), and with them the joint
    /// groups of woken members. In round `round` > 0 of the step's collision the bodies woken in
    /// earlier rounds wake those they touch as well; round 0 (particle pairs) takes no marks.
    Status wakeTouchedPairs(std::uint32_t round);
    /// Stage sleepBodies: restless marks from the rows, then each body's sleep.
    Status sleepBodies(float dt);
    /// SAT with the sleep on the host, after a round of the collision and the summaries (the
    /// status block read): when a body is asleep, HostSleep::wake over this round's pairs with
    /// rows and the velocities before the forces; the woken bodies' flags go to the device.
    /// Returns the bodies it woke (the caller collides again). Errors: Device.
    Result<std::uint32_t> wakeIslandsOnHost();
    /// SAT with the sleep on the host, once the step has run: HostSleep::update over the step's
    /// pairs with rows (colorPgs read them), on the velocities after the step (`readBack`'s,
    /// else read here); the bodies that fell asleep are stopped on the device and in `readBack`,
    /// and the flags go to the device. Returns the bodies asleep. Errors: Device.
    Result<std::uint32_t> updateIslandsOnHost(float dt, const std::optional<Bodies>& readBack);
    /// The summed impulse of the rows on each obstacle.
    Status gatherObstacleImpulses();
    /// Sorts `count` (key, value) pairs by the low `bits` of the key, stably; the result is in
    /// keys and values (the Alt buffers are scratch). With a status slot named, the count is
    /// the smaller of `count` and that slot's value, read on the device.
    Status radixSort(Buffer& keys, Buffer& values, Buffer& keysAlt, Buffer& valuesAlt,
                     std::uint32_t count, std::uint32_t bits,
                     std::uint32_t countSlot = RUBBLE_STATUS_COUNT);
    /// out[i] = sum of in[0..i-1] for i <= count.
    Status exclusiveScan(const Buffer& in, Buffer& out, std::uint32_t count);

    // The SAT method (host/gpu/broad_phase.cpp, host/gpu/sat.cpp), for a world made with
    // CollisionMethod::Sat; each the twin of SatCollision's stage of the same name. They only
    // enqueue; the pair count and the manifolds' contact count and largest depth are in the
    // status block (RUBBLE_STATUS_PAIRS, _CONTACTS, _PENETRATION).
    /// Stage broadPhase: computeAabbs, then findPairs.
    Status broadPhase(float dt);
    /// Each body's box grown by the margin and its reach this step, its spin and flags.
    Status computeAabbs(float dt);
    /// The grid, the candidate pairs (no two inactive bodies, none joined), sorted by (a, b).
    Status findPairs();
    /// Waits and reads the pair count; past the capacity the pair buffers grow and findPairs
    /// runs again. Returns the count. Errors: Device.
    Result<std::uint32_t> readPairCount();
    /// Stage narrowPhase: one manifold per pair, with last step's features (collideShapes).
    Status narrowPhase(float dt);
    /// This step's pairs and features become last step's (at the end of a step, after the
    /// manifolds were used; a step run again after an overflow calls it once), with SAT the
    /// still pairs of last step's set carried after them (carryStillPairs). Errors: Device.
    Status keepPairFeatures();
    /// SAT: last step's entries whose bodies both stood still in this step, that hold impulses
    /// and that this step did not find, carried after this step's pairs (kernels/pgs.cl,
    /// markStillPairs to carryStillPairs).
    Status carryStillPairs();
    /// SAT, in collision round `round`: the sleeping bodies that last step's entries with
    /// impulses join to a body woken in an earlier round wake (kernels/sleep.cl).
    Status wakeStillPairs(std::uint32_t round);
    /// Replaces this step's pairs (twin tests feed both paths the same pairs); sorted, a < b.
    Status uploadPairs(std::span<const BodyPair> pairs);
    /// Reads this step's pairs (readPairCount's count of them). Errors: Device.
    Result<std::vector<BodyPair>> downloadPairs();
    /// Reads this step's manifolds, one per pair. Errors: Device.
    Result<std::vector<shared::ContactManifold>> downloadManifolds();
    /// Reads the features of this step's pairs. Errors: Device.
    Result<std::vector<shared::PairCache>> downloadPairFeatures();
    /// Reads the bodies' boxes. Errors: Device.
    Result<std::vector<shared::BodyBox>> downloadBoxes();
    const SatBuffers& sat() const { return sat_; }

    // Projected Gauss-Seidel (host/gpu/pgs.cpp) for a world made with CollisionMethod::Sat; the
    // twin of PgsSolver's stages.
    /// Stage buildContactRows, before the host's coloring: each body's inverse mass and world
    /// inverse inertia (0 when it does not move), each pair's summary for the coloring (and the
    /// impulses kept by pairs that get no rows), the marks of the split position pass, the
    /// joints' rows.
    Status summarizePairs(const StepParams& params);
    /// Reads this round's pairs and their summaries into pairsHost and pairRowsHost, unless
    /// they are there already (the status block must have been read after the summaries).
    /// Errors: Device.
    Status readPairSummaries();
    /// Reads each pair's summary and colors the step's elements into PgsElement records with
    /// their rows packed in color order; the status block must have been read after the
    /// summaries (readStatus), and the pairs must fit their buffers. Errors: Device.
    Status colorPgs();
    /// Stage buildContactRows, after the coloring: the rows of every element's manifold points,
    /// warm-started.
    Status buildPgsRows(const StepParams& params);
    /// Stage solve: warm start, `iterations` velocity sweeps and the split position pass, one
    /// launch per color each; the momenta take up the velocity change. The pass's sweep k runs in
    /// the launches of velocity sweep k, unless a row may bounce (the status block read after
    /// the summaries): then the bouncing rows' lifts are marked (markBounces) after the velocity
    /// sweeps and the pass follows in launches of its own, as the CPU orders them.
    Status solvePgs(const StepParams& params);
    /// After integratePositions, when a row may bounce: the restitution pass (PgsSolver's
    /// solveRestitution, up to `iterations` sweeps, one launch per color), then the bounces'
    /// impulses into the momenta and those bodies' velocities from them.
    Status bouncePgs(const StepParams& params);
    /// After the restitution pass: the split position pass moves the bodies (nothing to
    /// enqueue when it did not run this step).
    Status applyPushes(float dt);
    /// After the pushes: the joints projected onto their constraints (a group of at most
    /// RUBBLE_JOINT_DIRECT_ROWS rows as one, up to RUBBLE_JOINT_POSITION_ITERATIONS Newton
    /// steps; larger groups joint by joint, color by color, as many sweeps); the jointed
    /// bodies' velocities follow.
    Status projectJoints();
    /// Reads this step's rows, packed in element order. Errors: Device.
    Result<std::vector<shared::PgsNormalRow>> downloadPgsNormalRows();
    Result<std::vector<shared::PgsFrictionRows>> downloadPgsFrictionRows();
    const PgsBuffers& pgs() const { return pgs_; }

    const ParticleBuffers& particles() const { return particles_; }
    const ContactBuffers& contacts() const { return contacts_; }
    const ObstacleBuffers& obstacles() const { return obstacles_; }
    /// Replaces this step's contacts (twin tests feed both paths the same set).
    Status uploadContacts(std::span<const shared::ParticleContact> contacts);
    /// Sets the contact capacity (and whether it may grow), for tests of overflow.
    Status setContactCapacity(std::uint32_t capacity, bool growable);

    /// Clears the status slots at the start of a step (enqueued), and reads them (waits).
    Status resetStatus();
    Result<DeviceStatus> readStatus();
    /// Waits until the queue is empty.
    Status finish();
    /// Device time of each kernel and transfer over the steps so far.
    std::vector<CommandTotals> profileTotals() const { return profile_.totals(); }
    /// Whether the steps keep each command's times for lastCommands().
    void keepCommands(bool keep) { profile_.keepCommands(keep); }
    /// The commands of the last step that was met, in the order they were enqueued (none unless
    /// kept).
    std::span<const DeviceCommand> lastCommands() const { return profile_.lastCommands(); }
    /// Adds the device times of the commands enqueued since the last step was met (or the last
    /// call; all must have completed) to the totals, kernels' bytes from `counts`: for
    /// benchmarks of single stages. Errors: Device.
    Result<DeviceTimes> collectProfile(const TrafficCounts& counts) {
        return profile_.collect(counts);
    }
    /// Carries another pipeline's totals on (a world's device arrays built again).
    void keepProfileOf(const Pipeline& old) { profile_.addTotals(old.profile_); }

  private:
    explicit Pipeline(std::shared_ptr<Context> context) : context_(std::move(context)) {}
    Status uploadParticles(const ParticleSet* set, BodiesView bodies,
                           std::span<const shared::float4> surfaces);
    Status uploadMassesAndFlags(std::span<const shared::BodyMass> masses);
    /// The SAT buffers: hulls, planes, joined pairs, per-body and pair arrays. Errors:
    /// NotSupported for a hull the device cannot clip (flattenShapes), Device.
    Status createSat(const PipelineInput& in);
    /// The SAT step's collision and rows: broad phase, narrow phase, PGS rows; then waits for
    /// the pair count, and when the pairs overflowed grows the buffers and runs them again.
    Status enqueueSatCollision(const StepParams& params);
    /// The SAT step from the solve to the end (particles with PGS too).
    Status enqueueSatSolve(const StepParams& params);
    /// The pair arrays and PGS's per-body buffers and joints, both sets of pairs sized for
    /// `guess` pairs: SAT's, or particles' with PGS. Errors: Device.
    Status createPairArrays(const PipelineInput& in, std::uint32_t guess);
    /// Particles with PGS, the step's collision and rows: particle contacts, sorted, into pairs
    /// of one point, the wake, the summaries; then waits for the status, and when the contacts
    /// overflowed grows the buffers and runs them again; the coloring and the rows.
    Status enqueueParticlePgs(const StepParams& params);
    /// After the pairs' manifolds: the wake before the rows (in collision round `round`, see
    /// wakeTouchedPairs) and the pairs' summaries, then waits for the status block (the host
    /// colors from it). Errors: Device.
    Result<DeviceStatus> wakeAndSummarize(const StepParams& params, std::uint32_t round);
    /// Projected Gauss-Seidel over the pair arrays: SAT, or particles with PGS.
    bool pairPgs() const { return sat_.enabled || particlePgs_; }
    /// The joints' buffers and the coloring of their position projection.
    Status createJoints(const PipelineInput& in);
    /// Sizes this step's pair buffers (and the manifolds) for `capacity` pairs.
    Status setPairCapacity(std::uint32_t capacity);
    /// The stages from collision to the end of the step, and the status read.
    Status enqueueFromCollision(const StepParams& params);
    /// After a contact overflow (`st`): the contact buffers (and with PGS the pairs') grown
    /// within the particles' budget, said on stderr (`again`: what runs again), and the status
    /// block's count and capacity set for the stages to run again. Errors: Numerical when the
    /// buffer may not grow, Limit past the budget (`step`: the step it names), Device.
    Status growContacts(const DeviceStatus& st, std::int64_t step, const char* again);
    /// Puts back last step's contacts as the warm start after a step whose contacts overflowed.
    void undoWarmStartSwap();
    /// The pairs with rows among pairsHost (pairRowsHost's points) into islands_.touching.
    void collectTouching();
    /// The joint groups' wake (kernels/sleep.cl wakeJointGroups): pass 0 marks the groups with
    /// an awake member, then `wakePass` (1 after sleepBodies, 2 before the solve) wakes them;
    /// pass 2 marks them with the collision round `collisionRound` when it is above 0.
    Status wakeJointGroups(cl_uint wakePass, cl_uint collisionRound = 0);
    /// Forces hold for one step: the device's are cleared once the step has used them.
    Status clearForces();
    /// The status block's read at the end of an enqueued step (endStep meets it), and the flush.
    Status enqueueStatusRead();
    DeviceStatus statusFromSlots() const;
    /// The global size of a stage whose work-items stride through up to `capacity` items in
    /// groups of `group`: enough groups to fill the device, no more than the items need.
    std::size_t strideItems(std::uint32_t capacity, std::size_t group) const;
    /// Sets one word of the status block (RUBBLE_STATUS_*), blocking. Errors: Device.
    Status writeStatusSlot(std::uint32_t slot, cl_uint value);
    /// The arguments summarizePairs and buildPgsRows both read, in their kernels' order: the
    /// rows' settings (baumgarte, slop, dt, warm start) and last step's pairs and impulses.
    void bindRowSettings(Dispatch& d, const StepParams& params) const;
    /// The arguments the kernels that go through this step's pairs read first, in their order:
    /// the pair buffers' capacity, the pair count (on the device) and the pairs.
    void bindPairs(Dispatch& d) const;
    /// The same of last step's set (its entries: its pairs and the still pairs it carried).
    void bindPreviousPairs(Dispatch& d) const;
    /// ... through the contacts.
    std::size_t strideItems() const {
        return strideItems(contacts_.capacity, RUBBLE_GROUP_CONTACTS);
    }
    /// ... through this step's pairs (SAT).
    std::size_t pairStrideItems() const {
        return strideItems(sat_.current.capacity, context_->workSizes().pairGroup);
    }

    std::shared_ptr<Context> context_;
    BodyBuffers bodies_;
    ParticleBuffers particles_;
    ContactBuffers contacts_;
    ObstacleBuffers obstacles_;
    SatBuffers sat_;
    PgsBuffers pgs_;
    HostIslands islands_;
    Buffer status_;
    Profile profile_;
    LcpBuffers lcp_;
    std::vector<std::uint8_t> kinematic_; ///< per body, as created
    bool deterministic_ = false;          ///< contacts sorted before the rows
    bool particlePgs_ = false;            ///< PipelineInput::particlePgs
    std::uint32_t pgsBlocks_ = 0;         ///< blocks of the PGS solve (0: colors only)
    std::uint32_t lcpStride_ = 1;         ///< rows per contact of lcp-jacobi (lcpStride)
    bool forcesOnDevice_ = false;         ///< the device force buffer holds non-zero forces
    bool stepPending_ = false;            ///< beginStep ran, endStep not yet
    std::optional<Bodies> readBack_;      ///< the step's StepInputs::readBack
    std::vector<cl_uint> flagsHost_;      ///< the flags read with them
    /// SAT: the pairs this step's collision found, and those of the set kept as last step's
    /// (enqueueSatSolve keeps a set of still pairs alone as it is); whether the host wrote body
    /// state since the last step.
    std::uint32_t pairsFound_ = 0, keptFound_ = 0;
    bool hostBodies_ = false;
    /// The bodies that move (neither static nor kinematic), counted at each upload (atRest).
    std::uint32_t movingBodies_ = 0;
    bool warmSwapped_ = false;            ///< this step's solve kept its contacts for the next
    bool gatherImpulses_ = false;         ///< this step reads the obstacles' impulses
    // Host memory the step's non-blocking transfers read from or write to.
    std::array<cl_uint, RUBBLE_STATUS_COUNT> statusInit_{}, statusHost_{};
    std::vector<shared::ObstacleState> obstaclesHost_;
    std::vector<shared::BodyImpulse> impulsesHost_;
};

} // namespace rubble::gpu
