// include/rubble/tools.h: the tables behind `rubble compare`, `rubble solvers` and
// `rubble devices`, computed for the command and for host programs (the Python package) alike;
// printing them is the caller's business (docs/solvers.md defines the numbers).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"
#include "rubble/world.h"

namespace rubble {

/// What one side of a comparison is at one compared step; dynamic bodies, world frame.
struct CompareSample {
    double kineticEnergy = 0;   ///< J
    double linearMomentum = 0;  ///< |sum P|, kg m/s
    double angularMomentum = 0; ///< |sum x x P + L| about the origin, kg m^2/s
    float penetration = 0;      ///< m, largest over the substeps that reached this step
    float residual = 0;         ///< the last substep's solver residual, N s
    std::uint32_t contacts = 0; ///< contact points of the last substep
};

/// One compared step: the divergence of the dynamic bodies' poses between the sides (position
/// distance and rotation angle, largest and root mean square) and each side's sample.
struct CompareRow {
    long long step = 0; ///< compared steps since the start; 0 is the scenes as loaded
    double time = 0;    ///< s
    double positionMax = 0, positionRms = 0; ///< m
    double angleMax = 0, angleRms = 0;       ///< rad
    CompareSample a, b;
};

/// One scene on two configurations stepped side by side (`rubble compare`). Move-only.
class Comparison {
  public:
    /// Builds the two worlds from scenes whose options are already set. The side with the
    /// smaller time step takes several steps per compared step. Errors: BadInput when the time
    /// steps are neither equal nor one a whole multiple of the other; those of World::create.
    static Result<Comparison> create(const Scene& a, const RunOptions& runA, const Scene& b,
                                     const RunOptions& runB);

    /// The compared step, s: the larger of the two time steps.
    double dt() const { return dt_; }
    const World& a() const { return *a_; }
    const World& b() const { return *b_; }

    /// The next compared step's row: step 0 (the scenes as loaded) on the first call, then both
    /// sides advanced to the same time. Errors: those of World::step; the worlds are then
    /// past use.
    Result<CompareRow> next();

  private:
    Comparison() = default;
    std::unique_ptr<World> a_, b_;
    int substepsA_ = 1, substepsB_ = 1;
    double dt_ = 0;
    long long step_ = 0;
};

/// One solver's errors on a frozen contact set after each iteration (docs/solvers.md).
struct SolverIterate {
    double residual = 0;        ///< m/s
    double complementarity = 0; ///< N m
    std::optional<double> velocityError; ///< m/s, against lemke's answer when it has one
};

/// One solver on one backend: its iterates, or why it did not run.
struct SolverHistory {
    std::string solver, backend;
    std::vector<SolverIterate> iterates; ///< after iteration 1, 2, ...
    std::string skipped;                 ///< empty when it ran
};

/// Every solver on one step's contact set (`rubble solvers`).
struct SolversTable {
    std::string collision;       ///< the collision method that found the contacts
    std::uint32_t contacts = 0;  ///< contact points
    std::uint32_t rows = 0;      ///< rows of the dense problem
    bool frictionless = false;   ///< normal rows only (every friction 0)
    std::vector<SolverHistory> histories; ///< pgs, jacobi (cpu, opencl), lcp-jacobi (cpu, opencl)
    std::optional<int> lemkePivots;       ///< lemke's exact answer, when it has one
    SolverIterate lemke;                  ///< lemke's errors (when lemkePivots is set)
    std::string lemkeSkipped;             ///< why lemke has no answer
};

/// Freezes the contact set of step `step` of `scene` on the CPU reference pipeline (the scene's
/// collision method, pgs; with `frictionless` every friction set to 0) and runs every solver on
/// it from zero impulses for `iterations` iterations, on the CPU and on the OpenCL device of
/// `run` (a missing device skips the device rows, saying why). Errors: BadInput for
/// iterations < 1, step < 1 or a step without contacts; those of World::create.
Result<SolversTable> compareSolvers(Scene scene, const RunOptions& run, int step, int iterations,
                                    bool frictionless);

/// What the solver suite runs (`rubble solvers --suite`, docs/solvers.md, "The solver test
/// set").
struct SuiteOptions {
    std::vector<std::string> scenes; ///< scene files
    int steps = 300;                 ///< steps of each run
    /// Constraint passes per step, the suite's equal cost: pgs, jacobi and lcp-jacobi take this
    /// many iterations, soft-step passes / (1 + relax) substeps of one biased and `relax`
    /// relaxing passes each (at least one substep).
    int passes = 10;
    int relax = 1;                   ///< soft step's relax passes per substep
    std::vector<std::string> paths{"cpu", "device-colored", "device-blocks"};
    std::vector<SolverType> solvers{SolverType::Pgs, SolverType::Jacobi, SolverType::LcpJacobi,
                                    SolverType::SoftStep};
    RunOptions run; ///< the device of the device paths
};

/// One scene, one solver, one path: what the run did (docs/solvers.md defines the columns).
struct SuiteRow {
    std::string scene, solver, path;
    std::string settings; ///< `iterations=10` or `substeps=5 relax=1`
    int steps = 0;        ///< steps taken (fewer when the run stopped)
    /// `yes` when the body named "top" ends within 0.1 m of where it started horizontally and
    /// upwards and sank less than 0.5 m, `no` otherwise, `-` for a scene without one
    std::string stands{"-"};
    /// The "top" body's (else the highest body's) distance from its start at the end, m
    double topDrift = 0;
    /// How far the same body moved over the run's second half, m: settling shows in the drift,
    /// a body that never comes to rest here too
    double topCreep = 0;
    double penetration = 0; ///< the deepest contact of any step, before its solve, m
    /// How far kinetic plus potential energy ever rose above the start's, J
    double energyGained = 0;
    double jointError = 0; ///< the largest anchor separation of any joint at any step, m
    double msPerStep = 0;  ///< wall time of the steps over their count
    std::string skipped;   ///< why the run did not happen or stopped; empty when it ran
};

/// Each scene on each path with each solver that the path has, at equal constraint passes.
/// A combination that cannot run (no device, no joint rows, no device soft step, too many rows)
/// is a row saying why. Errors: BadInput for steps or passes below 1 or a scene that does
/// not load.
Result<std::vector<SuiteRow>> runSolverSuite(const SuiteOptions& options);

/// One OpenCL device; `index` counts every device of every platform in order.
struct DeviceDesc {
    std::uint32_t index = 0;
    std::string platform, name;
    std::string version; ///< CL_DEVICE_VERSION
    std::string driver;  ///< CL_DRIVER_VERSION
    std::uint32_t computeUnits = 0;
    std::uint64_t globalMemory = 0;  ///< bytes
    std::uint64_t maxAllocation = 0; ///< bytes, the largest single buffer
};

/// Every OpenCL device of every platform (`rubble devices`). Errors: NotSupported when there
/// is no OpenCL platform (the message says how to install PoCL), Device for a failing query.
Result<std::vector<DeviceDesc>> openClDevices();

} // namespace rubble
