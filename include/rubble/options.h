// include/rubble/options.h: how a world is stepped. Scene files fill these; the command line
// overrides them. Nothing here is global: a World copies its Options at creation.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <glm/vec3.hpp>

#include "rubble/error.h"

namespace rubble {

namespace gpu {
class Context;
}

/// Time integration of the bodies' state.
enum class Integrator {
    Symplectic, ///< momenta first, then positions with the new velocities (default)
    Explicit,   ///< positions with the velocities from the start of the step
};

/// Where the bodies are stepped.
enum class Backend { Cpu, OpenCl };

/// How contacts are found.
enum class CollisionMethod {
    Sat,       ///< half-edge hulls, separating axes, clipped manifolds (CPU reference)
    Particles, ///< voxelised shapes as spheres on a uniform grid
};

/// How contact and joint impulses are solved.
enum class SolverType {
    Pgs,       ///< projected Gauss-Seidel, sequential impulses with warm start
    Jacobi,    ///< per-row parallel projected Jacobi, matrix-free
    LcpJacobi, ///< projected Jacobi on the dense Delassus matrix
    Lemke,     ///< exact LCP pivoting for small frictionless systems
    SoftStep,  ///< substeps with soft constraints, relax and restitution (Catto's soft step)
};

/// Whether debris on the device pushes the bodies on the CPU.
enum class Coupling { OneWay, TwoWay };

/// Who colors the device's Gauss-Seidel elements when no blocks are used (docs/opencl.md,
/// "Coloring by support" and "Coloring on the device"): the host each step (by support, a
/// blocking read of the pairs), or the device (a fixed number of colors and launches). Auto
/// takes the device's for the soft step and the host's for PGS, the one that keeps each
/// solver nearer the CPU reference (resolvePgsColoring).
enum class PgsColoring { Auto, Host, Device };

/// The `simulation.solver` block of a scene.
struct SolverOptions {
    /// When the scene does not say: pgs, on either backend and with either collision method
    /// (SimulationOptions::solverType; a world holds the one in effect).
    std::optional<SolverType> type;
    int iterations = 10;     ///< solver sweeps per step
    float baumgarte = 0.2f;  ///< fraction of the penetration corrected per step, 0..1
    float slop = 0.005f;     ///< penetration left uncorrected, m
    float relaxation = 1.0f; ///< over- or under-relaxation of each impulse update
    bool warmStart = true;   ///< start from last step's impulses matched by feature id
    // Soft step (docs/solvers.md, "Soft step"); the other solvers ignore these.
    int substeps = 4;               ///< substeps per step, each one biased pass
    int relaxIterations = 1;        ///< passes without bias after each substep's positions
    float contactHertz = 30.0f;     ///< contact stiffness, Hz (at most substep rate / 4)
    float dampingRatio = 10.0f;     ///< contact damping ratio
    float jointHertz = 60.0f;       ///< joint stiffness, Hz
    float jointDampingRatio = 2.0f; ///< joint damping ratio
    float maxPushSpeed = 3.0f;      ///< fastest a contact pushes overlapping bodies apart, m/s
};

/// The `simulation.collision` block of a scene.
struct CollisionOptions {
    /// When the scene does not say: sat on the cpu backend, particles on opencl
    /// (SimulationOptions::collisionMethod; a world holds the one in effect).
    std::optional<CollisionMethod> method;
    float particleSpacing = 0.1f; ///< voxel size of the particle representation, m
    /// Contact recycling (SAT on the CPU): a hull pair, or a body on a static level mesh, that has
    /// moved less than RUBBLE_RECYCLE_DISTANCE (0.25 mm) against itself since its manifolds were
    /// made keeps them, their separations recomputed, instead of running SAT or the triangle
    /// tests and clipping (docs/collision.md).
    bool recycleContacts = false;
};

/// The `simulation` block of a scene, after command-line overrides.
struct SimulationOptions {
    float dt = 1.0f / 60.0f; ///< time step, s
    int steps = 600;         ///< steps that `rubble run` takes
    glm::vec3 gravity{0.0f, -9.81f, 0.0f}; ///< m/s^2, world frame (y up)
    Integrator integrator = Integrator::Symplectic;
    Backend backend = Backend::Cpu;
    CollisionOptions collision;
    SolverOptions solver;
    Coupling coupling = Coupling::OneWay;
    /// Continuous collision: each pair's contact margin grows by how much closer its bodies can
    /// come in the step (speculative contacts), so that fast bodies do not pass through thin
    /// ones. Off, the margin is the fixed RUBBLE_CONTACT_MARGIN (the CPU's SAT path only).
    bool continuous = true;
    /// Whether still bodies go to sleep (CPU islands, the device's sleep); false keeps every
    /// body awake, as a benchmark that times every step's full work asks.
    bool sleep = true;

    /// The collision method in effect: the scene's, else the backend's default (sat on cpu,
    /// particles on opencl; SAT and PGS on the device are asked for by naming sat).
    CollisionMethod collisionMethod() const {
        if (collision.method) return *collision.method;
        return backend == Backend::OpenCl ? CollisionMethod::Particles : CollisionMethod::Sat;
    }
    /// The solver in effect: the scene's, else pgs, on either backend and with either collision
    /// method (a debris set on opencl takes jacobi whatever the scene says: deviceSolver).
    SolverType solverType() const { return solver.type.value_or(SolverType::Pgs); }
};

/// Choices that belong to the run rather than to the scene.
struct RunOptions {
    std::string device;    ///< OpenCL device by name fragment or index; empty: the first one
    std::string kernelDir; ///< load kernels/*.cl from here instead of the embedded text
    bool deterministic = false; ///< device rows sorted by key so atomics cannot reorder sums
    /// Blocks of the device's Gauss-Seidel solve (docs/opencl.md, "Blocks"): -1 as the device
    /// suits (a CPU device four per compute unit, a GPU none), 0 every element colored, N > 0
    /// that many blocks.
    int pgsBlocks = -1;
    /// Who colors the device's solve when it has no blocks (a GPU, or --pgs-blocks 0).
    PgsColoring pgsColoring = PgsColoring::Auto;
    /// SAT on the device: each body sleeps by itself on the device (its slow time and its
    /// neighbours', as the particle paths sleep) instead of by the CPU's islands.
    bool bodySleep = false;
    /// Options added to every OpenCL program build (`-cl-opt-disable` for Oclgrind).
    std::string buildOptions;
    /// Set to true (by a signal handler, another thread) to stop: World::step checks it between
    /// its stages and returns ErrorKind::Interrupted. Must outlive the World.
    const std::atomic<bool>* stop = nullptr;
    /// An OpenCL context with its program built (rubble::openDevice), shared by the worlds made
    /// with it so that the kernels compile once; empty: the world opens the device itself.
    std::shared_ptr<gpu::Context> context;
};

/// Scene-file spelling of each enum value, as in SCENE_FORMAT.md.
std::string_view toString(Integrator v);
std::string_view toString(Backend v);
std::string_view toString(CollisionMethod v);
std::string_view toString(SolverType v);
std::string_view toString(Coupling v);
std::string_view toString(PgsColoring v);
/// The coloring a run takes for `solver`: `chosen` unless it is Auto (then Device for the soft
/// step, Host otherwise).
PgsColoring resolvePgsColoring(PgsColoring chosen, SolverType solver);

/// Parses the scene-file spelling; std::nullopt for anything else.
std::optional<Integrator> parseIntegrator(std::string_view s);
std::optional<Backend> parseBackend(std::string_view s);
std::optional<CollisionMethod> parseCollisionMethod(std::string_view s);
std::optional<SolverType> parseSolverType(std::string_view s);
std::optional<Coupling> parseCoupling(std::string_view s);

/// Sets the option with this command-line name (`dt`, `particle-spacing`, `device`) from text, as
/// `--name TEXT` would: the one parser and range check that scene files, the command line and
/// `rubble compare` share (docs/scene-format.md's table of simulation options). Errors: BadInput
/// at `where` for a value that does not read or is out of range; NotSupported at `where` for a
/// name that is not an option of the command line.
Status setOptionText(std::string_view name, std::string_view text, const std::string& where,
                     SimulationOptions& simulation, RunOptions& run);

/// Every scene-file spelling of an enum's values, indexed by the value (help texts, errors).
template <class E> std::span<const std::string_view> spellings();
template <> std::span<const std::string_view> spellings<Integrator>();
template <> std::span<const std::string_view> spellings<Backend>();
template <> std::span<const std::string_view> spellings<CollisionMethod>();
template <> std::span<const std::string_view> spellings<SolverType>();
template <> std::span<const std::string_view> spellings<Coupling>();
template <> std::span<const std::string_view> spellings<PgsColoring>();

} // namespace rubble
