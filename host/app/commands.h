// host/app/commands.h: the subcommands of `rubble`, each filled by CLI11 in main.cpp.
#pragma once

#include <optional>
#include <string>

#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"

namespace rubble::app {

/// Exit statuses of the command.
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;   ///< I/O or device failure
constexpr int kExitBadInput = 2;  ///< bad scene, mesh or option; a feature not built yet
constexpr int kExitNumerical = 3; ///< the simulation blew up (a non-finite state)
constexpr int kExitInterrupted = 130;

/// Command-line overrides of a scene's `simulation` fields; unset ones leave the file's value.
struct Overrides {
    std::optional<int> steps;
    std::optional<float> dt;
    std::optional<std::string> backend, integrator, solver, collision;
    std::optional<int> iterations;
    std::optional<float> particleSpacing;
};

/// Applies overrides to a scene; BadInput naming the option for a value out of range.
Status applyOverrides(const Overrides& o, Scene& scene);

/// Prints an error to stderr as `rubble: where: message` and returns its exit status.
int report(const Error& e);

struct RunArgs {
    std::string scene;
    Overrides overrides;
    RunOptions run;
    std::string out;
    int every = 1;
    std::string metrics;
    bool quiet = false;
};
int runCommand(const RunArgs& args);

struct ValidateArgs {
    std::string scene;
};
int validateCommand(const ValidateArgs& args);

struct SweepArgs {
    std::string file;               ///< SWEEP.json (docs/python.md)
    std::optional<int> workers;     ///< local Dask workers
    std::string scheduler;          ///< a Dask scheduler's address instead of a local cluster
    std::string out;                ///< the table as CSV; stdout when empty
    std::string python = "python3"; ///< the interpreter with the package (RUBBLE_PYTHON)
};
/// Fills SweepArgs::python from the RUBBLE_PYTHON environment variable when it is set.
void sweepFromEnvironment(SweepArgs& args);
/// Hands the arguments to the Python package's sweep (as `python3 -m rubble sweep` would);
/// returns only when the interpreter could not be started.
int sweepCommand(const SweepArgs& args);

} // namespace rubble::app
