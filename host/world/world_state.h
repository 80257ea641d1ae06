// host/world/world_state.h: what a World owns: the body arrays (host/core/bodies.h), the scene's
// shapes, materials, joints and events, the stage objects of the CPU pipeline chosen when the
// world was built, the device pipeline of the OpenCL backend, and the step's statistics.
// Private to host/world: every other folder gets a view of what it reads.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/collision/collision_stage.h"
#include "host/core/bodies.h"
#include "host/dynamics/blowup_watch.h"
#include "host/dynamics/contact_solver.h"
#include "host/geometry/shape.h"
#include "host/gpu/pipeline_handle.h"
#include "host/world/offload.h"
#include "rubble/options.h"
#include "rubble/scene.h"
#include "rubble/shared/body.h"
#include "rubble/shared/obstacle.h"
#include "rubble/shared/pgs_joint.h"
#include "rubble/world.h"

namespace rubble {

using shared::BodyForce;
using shared::BodyMass;
using shared::BodyMomentum;
using shared::BodyPose;
using shared::BodyVelocity;

struct WorldState {
    std::string sceneName;
    std::vector<Warning> warnings; ///< found when the world was built
    SimulationOptions options;
    RunOptions run;

    std::vector<Shape> shapes;
    std::vector<ShapeGeometry> geometry; ///< the shapes as World::shape gives them
    std::vector<MaterialDesc> materials;

    // One entry per body, by index.
    std::vector<std::string> names;
    BodyArrays bodies;
    std::vector<std::uint8_t> debris;
    std::vector<shared::float4> surfaces; ///< friction and restitution (bodySurfaces)

    std::vector<JointDesc> joints;
    std::vector<BodyPair> joined; ///< the joints' body pairs, (min, max), sorted: no collision
    std::vector<EventDesc> events;
    std::vector<std::uint8_t> eventFired;

    std::int64_t step = 0;
    StepStats stats;
    /// Poses that kinematic bodies reach at the end of the next step (World::setKinematicTarget).
    std::vector<std::pair<std::uint32_t, BodyPose>> kinematicTargets;
    /// The same as the device places them, kept until the step is met.
    std::vector<shared::ObstacleState> deviceTargets;
    /// Kinematic bodies whose velocity the host set since the last step (setVelocity,
    /// setKinematicTarget), each once: the device takes their velocities from the host's copy at
    /// the start of the next step, without an upload of the bodies.
    std::vector<std::uint32_t> kinematicVelocitySet;
    /// The same as the device sets them, kept until the step is met.
    std::vector<shared::ObstacleState> deviceVelocities;

    // The CPU pipeline: its stages, chosen when the world is built, and this step's contacts.
    std::unique_ptr<CollisionStage> collision;
    std::unique_ptr<ContactSolver> solver;
    StepContacts contacts;
    BlowUpWatch blowUp; ///< energy since the last reference (the blow-up watch after each step)
    /// The blow-up watch on the device's sums of the bodies' energy (host/world/blowup_check.cpp):
    /// the lowest the device summed since the watch's reference (J) and the rounding it may
    /// carry (J); `known` once a step that read the bodies set them.
    struct DeviceEnergyWatch {
        bool known = false;
        double lowest = 0, lowestRounding = 0;
    } deviceEnergy;
    /// The device world has kinematic bodies: their motion is the host's, and the watch reads
    /// the bodies every step.
    bool deviceKinematic = false;
    // Scratch reused every step: the velocities before the solve, and at the start of the step
    // before the forces (restitution's approach speeds; explicit Euler moves positions with them).
    std::vector<BodyVelocity> velocitiesBeforeSolve;
    std::vector<BodyVelocity> velocitiesAtStart;

    // OpenCL backend: the device pipeline, which holds the current body state. The host arrays
    // are read back when asked for (hostStale) and go back up before the next device step when
    // the host changed them (hostDirty, forcesDirty).
    gpu::PipelineHandle device;
    bool hostStale = false;
    bool hostDirty = false;
    bool forcesDirty = false;
    /// Debris offloading: the CPU world of the bodies the device does not step, which are
    /// kinematic obstacles on the device (host/world/offload.h); null when the device steps
    /// every moving body.
    std::unique_ptr<Offload> offload;
    std::vector<EventDesc> dueEvents; ///< scratch: the events the device applies this step
    /// SAT on the device: the joints in their bodies' frames, made at the poses of the first
    /// attach (as the CPU solver makes them at its first step) and kept when the device arrays
    /// are built again.
    std::vector<shared::PgsJoint> deviceJoints;

    std::uint32_t bodyCount() const { return bodies.count(); }
    bool isStatic(std::uint32_t i) const { return bodies.isStatic(i); }
    double time() const { return double(step) * double(options.dt); }
    CollisionScene collisionScene() const { return {shapes, materials, joined}; }
    SolverScene solverScene() const {
        return {shapes, materials, surfaces, joints, joined, names};
    }
};

/// The state of a World, for host/world's own use (the CPU world of an offloaded world, the
/// contact set of `rubble solvers`).
struct WorldAccess {
    static WorldState& state(World& w) { return *w.s_; }
    static const WorldState& state(const World& w) { return *w.s_; }
};

} // namespace rubble
