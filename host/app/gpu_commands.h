// host/app/gpu_commands.h: the subcommands about OpenCL devices and the comparison of pipelines:
// `rubble devices`, `rubble compare`, `rubble solvers`; registered by main.cpp.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/app/commands.h"
#include "rubble/options.h"

namespace rubble::app {

/// Fills an empty RunOptions::device from the RUBBLE_DEVICE environment variable (read here,
/// once, and nowhere in the library).
void deviceFromEnvironment(RunOptions& run);

struct DevicesArgs {
    bool bandwidth = false; ///< measure the copy bandwidths of the chosen device and the host
    int megabytes = 256;    ///< size of each measured copy, MiB
    int repeats = 10;       ///< copies of each kind; the median is reported
    std::string scene;      ///< with --bandwidth: run it and set each kernel against them
    int steps = 120;
    Overrides overrides; ///< --particle-spacing for the scene's run; else the scene's
    bool sat = false; ///< the scene's run with SAT and PGS instead of particles and jacobi
    bool pgs = false; ///< the scene's particles solved with PGS instead of jacobi
    RunOptions run;
};

struct CompareArgs {
    std::string scene;
    int steps = 60;
    std::vector<std::string> a, b; ///< KEY=VALUE settings of each side
    std::string csv, plot;
    RunOptions run;
};

struct SolversArgs {
    std::string scene;
    int step = 30;
    int iterations = 50;
    std::string csv;
    Overrides overrides;       ///< --collision; else the scene's
    bool frictionless = false; ///< every material's friction set to 0, so that lemke can solve
    RunOptions run;
    // --suite: the solver test set instead of one frozen step (`scene` a file or a folder).
    bool suite = false;
    int steps = 300;
    int passes = 10;
    int relax = 1;
    std::vector<std::string> paths{"cpu", "device-colored", "device-blocks"};
};

/// The gpu subcommands of one `rubble` invocation, after parsing.
class GpuCommands {
  public:
    /// Adds `devices`, `compare` and `solvers` to the command line.
    explicit GpuCommands(CLI::App& app);
    /// When one of them was parsed, runs it, stores its exit status and returns true.
    bool dispatch(int& exitCode);

  private:
    CLI::App* devices_ = nullptr;
    CLI::App* compare_ = nullptr;
    CLI::App* solvers_ = nullptr;
    DevicesArgs devicesArgs_;
    CompareArgs compareArgs_;
    SolversArgs solversArgs_;
};

int devicesCommand(const DevicesArgs& args);
int compareCommand(const CompareArgs& args);
int solversCommand(const SolversArgs& args);

} // namespace rubble::app
