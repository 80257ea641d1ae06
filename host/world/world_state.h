// host/world/world_state.h: the arrays a World owns, split by access: hot (poses, velocities,
// momenta, forces) and cold (mass, shape, material, names). Sized at load; stages take spans.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/collision/collision_world.h"
#include "host/collision/contact.h"
#include "host/collision/particle_world.h"
#include "host/dynamics/blowup_watch.h"
#include "host/dynamics/body_sleep.h"
#include "host/dynamics/dynamics_world.h"
#include "host/dynamics/jacobi.h"
#include "host/dynamics/lcp_jacobi.h"
#include "host/geometry/shape.h"
#include "host/gpu/pipeline_handle.h"
#include "host/world/offload.h"
#include "rubble/options.h"
#include "rubble/scene.h"
#include "rubble/shared/body.h"
#include "rubble/world.h"

namespace rubble {

using shared::BodyForce;
using shared::BodyMass;
using shared::BodyMomentum;
using shared::BodyPose;
using shared::BodyVelocity;

struct WorldState {
    std::string sceneName;
    SimulationOptions options;
    RunOptions run;

    std::vector<Shape> shapes;
    std::vector<MaterialDesc> materials;

    // One entry per body, by index.
    std::vector<std::string> names;
    std::vector<BodyPose> poses;
    std::vector<BodyVelocity> velocities; ///< derived from momenta and pose
    std::vector<BodyMomentum> momenta;    ///< the state: P and L
    std::vector<BodyForce> forces;        ///< accumulated for the next step, then cleared
    std::vector<BodyMass> masses;
    std::vector<std::uint32_t> shapeOf;
    std::vector<std::uint32_t> materialOf;
    std::vector<std::uint8_t> debris;

    std::vector<JointDesc> joints;
    std::vector<BodyPair>
        joined; ///< the joints' body pairs, (min, max), sorted: they do not collide
    std::vector<EventDesc> events;
    std::vector<std::uint8_t> eventFired;

    std::int64_t step = 0;
    StepStats stats;

    // Contacts of the current step, and what each stage keeps between steps.
    std::vector<BodyPair> pairs;
    std::vector<Manifold> manifolds;
    CollisionCache collision;
    SolverCache solver;
    ParticleState particles;  ///< the particle collision method (CPU, and the device's source)
    JacobiState jacobi;       ///< the jacobi, lcp-jacobi and lemke solvers on the CPU
    BodySleepState bodySleep; ///< sleeping as on the device, for the device's solvers on the CPU
    DenseLcp lcp;             ///< the dense problem of lcp-jacobi and lemke on the CPU
    std::optional<Error> stepFailure; ///< a CPU stage that could not run this step
    BlowUpWatch blowUp;               ///< energy since the last reference (blow-up watch)
    std::vector<float> bodyRadii;     ///< scratch: each body's bounding radius, m

    // Scratch reused every step: the velocities before the solve, and at the start of the step
    // (explicit Euler moves positions with those).
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

    std::uint32_t bodyCount() const { return std::uint32_t(poses.size()); }
    bool isStatic(std::uint32_t i) const { return masses[i].inverseMass == 0.0f; }
    double time() const { return double(step) * double(options.dt); }
};

} // namespace rubble
