// host/app/commands.h: the subcommands of `rubble`, each filled by CLI11 in main.cpp.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "host/core/option_table.h"
#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"
#include "rubble/world.h"

namespace CLI {
class App;
}

namespace rubble::app {

/// Exit statuses of the command.
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;   ///< I/O or device failure
constexpr int kExitBadInput = 2;  ///< bad scene, mesh or option; a feature not built yet
constexpr int kExitNumerical = 3; ///< the simulation blew up (a non-finite state, energy, a joint)
constexpr int kExitLimit = 4;     ///< a step needed more than a limit allows (pairs, contacts, memory)
constexpr int kExitInterrupted = 130; ///< SIGINT (128 + 2)
constexpr int kExitTerminated = 143;  ///< SIGTERM (128 + 15)

/// Command-line overrides of a scene's `simulation` options, as given and in order; unset ones
/// leave the file's value. The option table reads and checks them when they are applied.
struct Overrides {
    struct Item {
        const Option* option = nullptr;
        std::string where; ///< what named it, for errors: `--dt`, `--a dt=0.01`
        std::string text;  ///< the value as given
    };
    std::vector<Item> items;
};

/// Applies overrides to a scene; BadInput naming the flag or setting for a value that does not
/// read as the option's kind or is out of its range.
Status applyOverrides(const Overrides& o, Scene& scene);

/// Adds a command-line flag `--name` for every simulation option of the table that has one
/// (--dt, --steps, --solver, ...); their values land in `o`, checked by applyOverrides.
void addOverrideFlags(CLI::App* cmd, Overrides& o);
/// Adds the flag of one simulation option, by its command-line name (`particle-spacing`).
void addOverrideFlag(CLI::App* cmd, std::string_view name, Overrides& o);
/// Adds the flags of the table's run options (--device, --kernel-dir, --deterministic); each
/// is read into `run` as it is parsed.
void addRunFlags(CLI::App* cmd, RunOptions& run);
/// Adds the flag of one run option, by its command-line name (`device`).
void addRunFlag(CLI::App* cmd, std::string_view name, RunOptions& run);

/// Prints an error to stderr as `rubble: where: message` and returns its exit status.
int report(const Error& e);
/// Prints the world's warnings to stderr, each as `rubble: warning: where: message`.
void reportWarnings(const World& world);

struct RunArgs {
    std::string scene;
    Overrides overrides;
    RunOptions run;
    std::string out;
    int every = 1;
    std::string metrics;
    std::string trace; ///< the device's commands as Chrome trace events (opencl backend)
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
