// host/gpu/pipeline.h: the OpenCL pipeline of one world (DESIGN.md, "One step, OpenCL
// pipeline"): the device arrays, uploaded at load and kept there, and one method per stage.
// Each stage's dispatch lives in host/gpu/<stage>.cpp; its CPU twin has the same name.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>

#include "host/gpu/buffer.h"
#include "host/gpu/context.h"
#include "host/gpu/lcp_jacobi.h"
#include "host/gpu/pipeline_handle.h"
#include "rubble/shared/contact_row.h"
#include "rubble/world.h"

namespace rubble {
struct WorldState;
}

namespace rubble::gpu {

/// The body arrays on the device, one element per body in world order.
struct BodyBuffers {
    std::uint32_t count = 0;
    Buffer poses, velocities, momenta, forces, masses;
    Buffer atStart; ///< velocities at the start of the step (explicit Euler)
    Buffer before;  ///< velocities before the solve
};

/// The particles and the grid over them.
struct ParticleBuffers {
    std::uint32_t count = 0, staticCount = 0, bits = 0;
    float cellSize = 0; ///< m
    Buffer records, statics, world;
    Buffer keys, values, keysAlt, valuesAlt; ///< sorted cell keys and particles (ping-pong)
    Buffer histogram, offsets;               ///< radix sort counts and their exclusive scan
    Buffer cellStart, cellEnd;
};

/// Contacts, rows, the per-body row lists, and last step's contacts for warm starting.
struct ContactBuffers {
    std::uint32_t capacity = 0, count = 0, previousCount = 0;
    bool growable = true; ///< grow on overflow (tests turn it off to see the error)
    Buffer contacts, previous, unsorted;
    Buffer rows, previousRows;
    Buffer bodyCount, bodyStart, cursor, bodyList;
    Buffer head, next; ///< last step's contacts chained per particle
    Buffer surfaces;   ///< per body: friction, restitution
    Buffer sortKeys, sortValues, sortKeysAlt, sortValuesAlt;
};

/// What the host reads at the end of a step (RUBBLE_STATUS_* slots).
struct DeviceStatus {
    std::uint32_t contacts = 0;
    std::uint32_t firstNonFinite = 0xffffffffu; ///< a body index, or none
    float largestPenetration = 0;               ///< m
    float solverResidual = 0;                   ///< N s
};

class Pipeline {
  public:
    /// Sizes the device arrays for a world and uploads its bodies. Errors: Device.
    static Result<PipelineHandle> create(std::shared_ptr<Context> context, const WorldState& s);

    const Context& context() const { return *context_; }
    const std::shared_ptr<Context>& sharedContext() const { return context_; }
    const BodyBuffers& bodies() const { return bodies_; }

    /// Copies the host's poses, velocities, momenta and masses to the device: at load, and when
    /// the host changed them (impulses, events). Errors: Device.
    Status uploadBodies(const WorldState& s);
    /// Reads poses, velocities and momenta back into the host arrays, for whoever asked for
    /// the state (World::body, writers, metrics). Errors: Device.
    Status downloadBodies(WorldState& s);
    /// This step's forces and torques (World::addForce), uploaded when any were added.
    Status uploadForces(std::span<const shared::BodyForce> forces);

    /// One whole step on the device; the stage timings go into `stats`. Errors: Device,
    /// Numerical (a body that is not finite, named).
    Status step(WorldState& s, StepStats& stats);

    // Stages, each the twin of the CPU function of the same name.
    Status integrateVelocities(shared::float4 gravity, float dt);
    Status absorbVelocityChange();
    Status integratePositions(float dt, bool symplectic);
    /// Copies the velocities into `to` (atStart or before).
    Status copyVelocities(Buffer& to);
    Status transformParticles();
    /// Cell keys, the radix sort, the cell ranges.
    Status buildGrid();
    /// Contacts into the contact buffer; on overflow the buffer grows and the stage runs again
    /// (said on stderr), or, when it may not grow, an error. Reads the contact count back.
    Status collideParticles();
    /// Deterministic mode: contacts ordered by a stable sort on their particle.
    Status sortContacts();
    /// Row lists per body, warm start, rows.
    Status buildJacobiRows(const shared::SolverParams& params, bool warmStart);
    /// Copies the velocities to `before`, then `iterations` sweeps (rows, then the gather), and
    /// keeps this step's contacts and rows for the next step's warm start.
    Status solveJacobi(int iterations, float relaxation, bool warmStart);
    /// lcp-jacobi: the dense problem from the rows (`stride` rows per contact), `iterations`
    /// sweeps, the impulses back into the rows; solveJacobi(0, ...) then applies them.
    Status solveLcpJacobi(std::uint32_t stride, int iterations, float relaxation);
    /// Sorts `count` (key, value) pairs by the low `bits` of the key, stably; the result is in
    /// keys and values (the Alt buffers are scratch).
    Status radixSort(Buffer& keys, Buffer& values, Buffer& keysAlt, Buffer& valuesAlt,
                     std::uint32_t count, std::uint32_t bits);
    /// out[i] = sum of in[0..i-1] for i <= count.
    Status exclusiveScan(const Buffer& in, Buffer& out, std::uint32_t count);

    const ParticleBuffers& particles() const { return particles_; }
    const ContactBuffers& contacts() const { return contacts_; }
    /// Replaces this step's contacts (twin tests feed both paths the same set).
    Status uploadContacts(std::span<const shared::ParticleContact> contacts);
    /// Sets the contact capacity (and whether it may grow), for tests of overflow.
    Status setContactCapacity(std::uint32_t capacity, bool growable);

    /// Clears the status slots at the start of a step, and reads them at its end.
    Status resetStatus();
    Result<DeviceStatus> readStatus();
    /// Waits until the queue is empty (stage timings, transfers).
    Status finish();

  private:
    explicit Pipeline(std::shared_ptr<Context> context) : context_(std::move(context)) {}
    std::shared_ptr<Context> context_;
    Status uploadParticles(const WorldState& s);
    BodyBuffers bodies_;
    ParticleBuffers particles_;
    ContactBuffers contacts_;
    LcpBuffers lcp_;
    Buffer status_;
    bool forcesOnDevice_ = false; ///< the device force buffer holds non-zero forces
};

} // namespace rubble::gpu
