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
constexpr int kExitNumerical = 3; ///< the simulation blew up (a non-finite state, energy, a joint)
constexpr int kExitLimit = 4;     ///< a step needed more than a limit allows (pairs, contacts, memory)
constexpr int kExitInterrupted = 130; ///< SIGINT (128 + 2)
constexpr int kExitTerminated = 143;  ///< SIGTERM (128 + 15)

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

} // namespace rubble::app
