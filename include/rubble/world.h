// include/rubble/world.h: a simulated world built from a Scene, stepped on the CPU reference
// pipeline or the OpenCL pipeline, with queries and forces for a host program.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"
#include "rubble/shape.h"

namespace rubble {

struct WorldState;
namespace gpu {
class Context;
}

/// One body's state as a host program sees it; world frame, SI units.
struct BodyState {
    glm::vec3 position{0.0f};          ///< centre of mass, m
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f}; ///< body to world
    glm::vec3 linearVelocity{0.0f};    ///< m/s
    glm::vec3 angularVelocity{0.0f};   ///< rad/s
    glm::vec3 linearMomentum{0.0f};    ///< kg m/s
    glm::vec3 angularMomentum{0.0f};   ///< about the centre of mass, kg m^2/s
    float mass = 0.0f;                 ///< kg; 0 for static and kinematic bodies
    glm::mat3 inertia{0.0f};           ///< body frame, about the centre of mass, kg m^2
    bool isStatic = false;             ///< infinite mass: a static or a kinematic body
    bool isKinematic = false;          ///< moved by its velocities or a target pose only
    bool asleep = false;
};

/// Stacks stand with masses up to this ratio between their bodies (heavy on light), with the
/// reference solver at its default settings; World::warnings names the bodies past it.
inline constexpr float kStackMassRatio = 100.0f;

/// Something a scene asks that rubble does not promise to handle well (World::warnings).
struct Warning {
    std::string where;   ///< the file, and the bodies or fields concerned
    std::string message; ///< what may go wrong, and where the limit is documented

    /// The warning as one line, `where: message`.
    std::string describe() const { return where.empty() ? message : where + ": " + message; }
};

/// One contact point of the last step, world frame.
struct ContactInfo {
    std::uint32_t a = 0, b = 0;         ///< the bodies; the normal points from a to b
    glm::vec3 position{0.0f};           ///< midway between the surfaces, m
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< unit
    float depth = 0.0f;                 ///< penetration, m (negative: a gap the step may close)
};

/// Device time of each stage of the last step on the OpenCL device (profiling events), ms.
struct DeviceStageMs {
    double applyForces = 0;         ///< obstacles placed, explosions
    double integrateVelocities = 0;
    double broadPhase = 0;          ///< particles transformed, the grid
    double narrowPhase = 0;         ///< particle collision
    double buildContactRows = 0;
    double solve = 0;
    double integratePositions = 0;
    double sleep = 0;               ///< sleeping and waking, impulses gathered for the host
};

/// A stage of a step's times (`Stats`: DeviceStageMs, or StepStats for the CPU's stages): its
/// name in the metrics file (device_stages_ms, stages_ms) and in a trace (`cat`), and its field.
template <class Stats> struct StageField {
    std::string_view name;
    double Stats::*ms;
};
using DeviceStageField = StageField<DeviceStageMs>;

/// The device's stages in the order of a step.
inline constexpr DeviceStageField kDeviceStageFields[] = {
    {"apply_forces", &DeviceStageMs::applyForces},
    {"integrate_velocities", &DeviceStageMs::integrateVelocities},
    {"broad_phase", &DeviceStageMs::broadPhase},
    {"narrow_phase", &DeviceStageMs::narrowPhase},
    {"build_contact_rows", &DeviceStageMs::buildContactRows},
    {"solve", &DeviceStageMs::solve},
    {"integrate_positions", &DeviceStageMs::integratePositions},
    {"sleep", &DeviceStageMs::sleep}};

/// Milliseconds spent in each stage of the last step, and what it produced. The stage fields
/// are host wall time of the CPU pipeline; a world whose every moving body is on the OpenCL
/// device has no CPU stages and reports its device stage times there instead.
struct StepStats {
    double applyForcesMs = 0, integrateVelocitiesMs = 0, broadPhaseMs = 0, narrowPhaseMs = 0,
           buildContactRowsMs = 0, solveMs = 0, integratePositionsMs = 0, solvePositionsMs = 0,
           islandsMs = 0;
    double totalMs = 0;             ///< wall time of World::step
    std::uint32_t pairCount = 0;    ///< broad-phase pairs
    std::uint32_t contactCount = 0; ///< contact points (both populations)
    std::uint32_t asleep = 0;       ///< bodies asleep after the step (both populations)
    float largestPenetration = 0;   ///< m, before the solve
    float solverResidual = 0;       ///< largest |impulse change| in the last sweep, N s

    // The OpenCL device's part of the step, which runs while the host steps its own bodies.
    double hostMs = 0;         ///< host time of the step other than waiting for the device
    double deviceMs = 0;       ///< device busy time: the sum of its commands' durations
    double deviceWaitMs = 0;   ///< host time spent waiting for the device to finish the step
    /// Device time that ran while the host worked: deviceMs - deviceWaitMs, at least 0 (the
    /// device is busy from the enqueue to its end, so what the host did not wait for was hidden).
    double deviceHiddenMs = 0;
    DeviceStageMs deviceStages;
    std::uint32_t deviceContactCount = 0; ///< contact points on the device (its rows / 3)
    std::uint32_t deviceAsleep = 0;       ///< device bodies asleep after the step
    /// Times the host waited for the device within the step (blocking reads), besides the wait
    /// at its end; a steady SAT step on the device's plan waits none.
    std::uint32_t deviceWaits = 0;
};

/// One device kernel's (or kind of transfer's) total over the steps taken so far.
struct DeviceCommandTime {
    std::string name;
    double ms = 0;              ///< device time, profiling events
    std::uint64_t launches = 0;
    std::uint64_t bytes = 0;    ///< moved: a transfer's, or a kernel's (counted from its code)
};

/// One buffer the OpenCL device holds now: the call in host/gpu that made it ("pairs.cpp:80")
/// and its size.
struct DeviceBuffer {
    std::string where;
    std::uint64_t bytes = 0;
};

/// One command the OpenCL device ran in the last step, from its profiling event: the times are
/// the device clock's (CL_PROFILING_COMMAND_QUEUED, _SUBMIT, _START, _END), ns from a zero of the
/// device's own (DeviceClockSample relates it to the host's clock).
struct DeviceCommand {
    std::string_view name;  ///< the kernel, or the transfer (`(write to device)`); static text
    std::string_view stage; ///< its stage, a key of the metrics' device_stages_ms; static text
    std::uint64_t queuedNs = 0; ///< the host enqueued it
    std::uint64_t submitNs = 0; ///< the queue handed it to the device
    std::uint64_t startNs = 0;  ///< it began to run
    std::uint64_t endNs = 0;    ///< it was done
};

/// One moment seen on both clocks: the device clock's time at which the host enqueued a marker
/// (its CL_PROFILING_COMMAND_QUEUED), and the host's std::chrono::steady_clock just before and
/// just after the enqueue, ns since the steady clock's epoch. The device time lies between the
/// two host times, so device - host is known to within half their difference.
struct DeviceClockSample {
    std::uint64_t deviceNs = 0;
    std::int64_t hostBeforeNs = 0;
    std::int64_t hostAfterNs = 0;
};

/// A body's pose for drawing, 32 bytes: the layout of the device's pose records, so that bodies on
/// the OpenCL device are read into it without conversion.
struct BodyTransform {
    glm::vec4 position{0.0f};                      ///< centre of mass, world, m (w unused)
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f}; ///< body to world, stored x, y, z, w
};

/// One piece of debris for World::addDebris: a shape of the scene, its mass, where it starts.
struct DebrisPiece {
    std::string name;                              ///< the body's name (need not be unique)
    std::uint32_t shape = 0;                       ///< a shape of the scene (World::findShape)
    std::uint32_t material = 0;                    ///< a material of the scene; 0 is "default"
    float mass = 1.0f;                             ///< kg, > 0
    glm::vec3 position{0.0f};                      ///< centre of mass, world, m
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f}; ///< body to world
    glm::vec3 linearVelocity{0.0f};                ///< m/s
    glm::vec3 angularVelocity{0.0f};               ///< rad/s, world frame
};

/// Opens an OpenCL device (RunOptions::device) and builds the program, for worlds to share
/// through RunOptions::context so that the kernels compile once. Errors: NotSupported when no
/// OpenCL platform exists, Device for a failed build (with its log).
Result<std::shared_ptr<gpu::Context>> openDevice(const RunOptions& run);

/// The world summed up now (World::metrics): over the dynamic bodies unless said otherwise,
/// world frame, SI units; the last step's figures are those of World::lastStep.
struct WorldMetrics {
    double time = 0;                  ///< s
    std::int64_t step = 0;            ///< steps taken
    std::uint32_t bodies = 0;         ///< every body, static ones included
    std::uint32_t dynamicBodies = 0;
    std::uint32_t asleepBodies = 0;   ///< dynamic bodies asleep
    double kineticEnergy = 0;         ///< J, translational plus rotational
    double potentialEnergy = 0;       ///< J, -sum m g.x (zero at the world origin)
    glm::dvec3 linearMomentum{0.0};   ///< kg m/s
    glm::dvec3 angularMomentum{0.0};  ///< kg m^2/s, about the world origin
    double maxSpeed = 0;              ///< m/s, the fastest centre of mass
    glm::dvec3 centreOfMass{0.0};     ///< m; the origin when there is no dynamic body
    glm::vec3 lo{0.0f}, hi{0.0f};     ///< box around the centres of mass, m
    std::uint32_t contacts = 0;       ///< contact points of the last step (both populations)
    float largestPenetration = 0;     ///< m, in the last step
    float solverResidual = 0;         ///< N s, the last step's last sweep
    double stepMs = 0;                ///< wall time of the last step
};

/// A simulated world. Move-only.
class World {
  public:
    /// Builds the world of a scene: shapes (hulls, mass properties), bodies, joints, and the
    /// backend's resources. Errors: BadInput naming the scene field (degenerate hull, bad mass),
    /// NotSupported for a specified feature not built yet, Device for OpenCL failures.
    static Result<World> create(const Scene& scene, const RunOptions& run = {});

    World(World&&) noexcept;
    World& operator=(World&&) noexcept;
    ~World();

    /// Advances one step of options().dt. Errors: Numerical when a body's state becomes NaN or
    /// infinite (the message names the body and the step); stepping further is meaningless.
    Status step();

    /// Steps taken so far and the simulated time, s.
    std::int64_t stepIndex() const;
    double time() const;

    const SimulationOptions& options() const;
    const std::string& sceneName() const;
    /// What the scene asks past rubble's promises, found when the world was built; the world
    /// runs anyway. Each names the file and the bodies (`where`) and says what may go wrong:
    /// dynamic bodies whose masses differ more than kStackMassRatio times (stacks past that may
    /// sink or tip, docs/dynamics.md "Mass ratios"). The command prints them on stderr.
    std::span<const Warning> warnings() const;

    /// Bodies are indexed 0..bodyCount()-1 in scene order.
    std::uint32_t bodyCount() const;
    const std::string& bodyName(std::uint32_t body) const;
    std::optional<std::uint32_t> findBody(std::string_view name) const;
    BodyState body(std::uint32_t body) const;

    /// Adds a force (N, world frame) at the centre of mass for the next step only.
    void addForce(std::uint32_t body, glm::vec3 force);
    /// Adds a torque (N m, world frame) for the next step only.
    void addTorque(std::uint32_t body, glm::vec3 torque);
    /// Adds a force (N) at a world point (m) for the next step only.
    void addForceAtPoint(std::uint32_t body, glm::vec3 force, glm::vec3 point);
    /// Applies an impulse (N s) at a world point (m) now, and wakes the body.
    void applyImpulse(std::uint32_t body, glm::vec3 impulse, glm::vec3 point);

    /// Statistics of the last step.
    const StepStats& lastStep() const;

    /// Index of the scene shape with that name, if any.
    std::optional<std::uint32_t> findShape(std::string_view name) const;

    /// Adds pieces of debris after the last body, in order, and returns the index of the first.
    /// On the opencl backend they join the bodies the OpenCL device steps: the device arrays are
    /// sized again and uploaded whole, and the last step's contacts are forgotten (their warm
    /// start), so add many at once rather than one at a time. On the cpu backend they are
    /// ordinary bodies. Errors: BadInput naming the piece for a shape or material that does not
    /// exist, a plane, or a mass that is not > 0; Device.
    Result<std::uint32_t> addDebris(std::span<const DebrisPiece> pieces);

    /// Removes every body of the debris set (the scene's `debris` flag, or World::addDebris)
    /// whose centre of mass is outside the box [lo, hi] (world, m), except bodies with joints,
    /// and returns how many went. The other bodies keep their order, so the index of a body
    /// after a removed one goes down. The device arrays are rebuilt as by addDebris.
    /// Errors: BadInput when lo > hi on an axis; Device.
    Result<std::uint32_t> removeDebrisOutside(glm::vec3 lo, glm::vec3 hi);

    /// Copies the poses of bodies first .. first + out.size() - 1 into `out`, for drawing.
    /// Bodies on the OpenCL device are read straight from it and nothing else is read back, so
    /// this is the cheap way to draw every frame. Errors: BadInput for a range past the last
    /// body; Device.
    Status readTransforms(std::uint32_t first, std::span<BodyTransform> out) const;

    /// Copies the centres of mass (world, m) of bodies first .. first + out.size() / 3 - 1 into
    /// `out`, three floats (x, y, z) a body, so that a caller's array is filled in one pass.
    /// Bodies on the OpenCL device are read back once for this and the other reads.
    /// Errors: BadInput for a size that is not a multiple of 3 or a range past the last body;
    /// Device.
    Status readPositions(std::uint32_t first, std::span<float> out) const;
    /// As readPositions, the orientations (body to world), four floats a body: w, x, y, z.
    Status readOrientations(std::uint32_t first, std::span<float> out) const;
    /// As readPositions, the linear velocities of the centres of mass (world, m/s).
    Status readLinearVelocities(std::uint32_t first, std::span<float> out) const;
    /// As readPositions, the angular velocities (world, rad/s).
    Status readAngularVelocities(std::uint32_t first, std::span<float> out) const;

    /// Sets a dynamic body's linear (m/s) and angular (rad/s) velocity, world frame, now, and
    /// wakes it; its momenta follow (P = m v, L = I_w w). A kinematic body takes the velocities
    /// as they are (it has no momenta) and moves by them from the next step on. Errors:
    /// BadInput for a body index past the last, a static body or a velocity that is not finite;
    /// Device.
    Status setVelocity(std::uint32_t body, glm::vec3 linear, glm::vec3 angular);

    /// Moves a kinematic body to a pose (position of its centre of mass, m; orientation, body to
    /// world) over the next step: its velocities become those that reach the pose in one step
    /// (what the contacts with it see), and the step ends with the body at the pose. It keeps
    /// these velocities afterwards unless given another target or setVelocity. Errors:
    /// BadInput for a body index past the last, a body that is not kinematic, or a pose that
    /// is not finite.
    Status setKinematicTarget(std::uint32_t body, glm::vec3 position, glm::quat orientation);

    /// Index of the scene material with that name, if any; 0 is "default".
    std::optional<std::uint32_t> findMaterial(std::string_view name) const;

    /// Adds an explosion now: at the start of the next step every dynamic body within `radius`
    /// (m) of `centre` (world, m) receives impulse * (1 - d / radius) N s away from the centre,
    /// as a scene's explosion event (SCENE_FORMAT.md, Events). Errors: BadInput naming the
    /// argument for a negative or non-finite impulse, a radius that is not > 0, or a centre
    /// that is not finite.
    Status explode(glm::vec3 centre, float impulse, float radius);


    /// The world summed up now (energies, momenta, speed, extent, sleep) with the last step's
    /// contact figures. Bodies on the OpenCL device are read back first; a failed read is
    /// reported on stderr and the last copy is used, as World::body does.
    WorldMetrics metrics() const;

    /// The OpenCL device's name, or "cpu".
    std::string deviceName() const;
    /// Device time of each kernel and transfer over the steps so far (empty on the cpu backend).
    std::vector<DeviceCommandTime> deviceProfile() const;
    /// The device's buffers now, the largest first, and the most bytes they held at once so far
    /// (empty and 0 on the cpu backend).
    std::vector<DeviceBuffer> deviceBuffers() const;
    std::uint64_t deviceBytesPeak() const;
    /// How many times the device's bodies were read back to the host so far (a trajectory row,
    /// a query after a step, the blow-up watch when its energy sum nears the allowance); 0
    /// without a device.
    std::uint64_t deviceBodyReads() const;
    /// Whether the steps from now on keep each device command's times for lastDeviceCommands()
    /// (off by default: two more profiling queries per command). No effect on the cpu backend.
    void keepDeviceCommands(bool keep);
    /// The device's commands of the last step in the order they were enqueued, which is the
    /// order the device's in-order queue ran them in (empty on the cpu backend, before the
    /// first step, and unless keepDeviceCommands(true)); valid until the next step.
    std::span<const DeviceCommand> lastDeviceCommands() const;
    /// Relates the device's clock to the host's: enqueues a few markers on the device's queue
    /// and waits for them (call it between steps; the bodies are not touched). Errors:
    /// NotSupported on the cpu backend, Device.
    Result<DeviceClockSample> sampleDeviceClock() const;

    /// The shapes of the scene, by index, as built (centre of mass at the origin).
    std::span<const ShapeGeometry> shapes() const;
    const ShapeGeometry& shape(std::uint32_t shape) const;
    /// The shape of a body, an index for shape().
    std::uint32_t bodyShape(std::uint32_t body) const;
    /// Whether a body belongs to the debris set (the scene's `debris` flag, or addDebris).
    bool isDebris(std::uint32_t body) const;
    /// Whether the OpenCL device steps the body (false on the cpu backend, for static bodies
    /// and for the bodies an offloaded world steps on the CPU).
    bool onDevice(std::uint32_t body) const;
    /// The scene's joints, bodies by index.
    std::span<const JointDesc> joints() const;
    /// The contact points of the last step that the host found: every contact on the cpu
    /// backend, and those of the CPU bodies of an offloaded scene on the opencl backend (the
    /// device's own contacts stay on the device; their number is lastStep().deviceContactCount).
    /// Empty before the first step.
    std::vector<ContactInfo> contacts() const;
    /// The linear impulse (N s, world frame) that the debris on the OpenCL device put on the
    /// CPU bodies of an offloaded world in the last step, which they take at the start of the
    /// next (two-way coupling lags one step); zero otherwise. Momentum is conserved counting it.
    glm::vec3 pendingCouplingImpulse() const;
    /// The largest |impulse change| of each solver sweep of the last step on the CPU, N s
    /// (empty for the lemke solver and for a world stepped wholly on the device).
    std::span<const float> solverResiduals() const;

  private:
    friend struct WorldAccess; // host/world's own reach into a world it holds (offloading)
    explicit World(std::unique_ptr<WorldState> s);
    std::unique_ptr<WorldState> s_;
};

} // namespace rubble
