// host/app/main.cpp: the `rubble` command: subcommands and their options (CLI11); the flags of
// simulation and run options come from the option table (host/core/option_table.h).
#include <cstdio>
#include <cstdlib>

#include <CLI/CLI.hpp>

#include "host/app/commands.h"
#include "host/app/gpu_commands.h"
#include "host/app/viewer_commands.h"
#include "rubble/version.h"

int main(int argc, char** argv) {
    using namespace rubble::app;
    CLI::App app{"rubble: rigid-body simulation on the CPU and on OpenCL devices"};
    app.footer("Examples:\n"
               "  rubble run scenes/pyramid_20.json --out pyramid.csv --metrics pyramid.json\n"
               "  rubble run scenes/bench/debris_1k.json --steps 120 --every 10 --out debris.jsonl\n"
               "  rubble validate scenes/ragdoll.json\n"
               "Exit status: 0 done, 1 I/O or device failure, 2 bad input, 3 the simulation blew "
               "up\n(non-finite state, energy growth, a joint apart), 4 a limit reached (pairs, "
               "contacts,\nparticles, memory), 130 interrupted (SIGINT), 143 terminated (SIGTERM).");
    app.set_version_flag("--version", std::string("rubble ") + rubble::kVersion);
    app.require_subcommand(1);

    RunArgs run;
    CLI::App* runCmd = app.add_subcommand("run", "Simulate a scene and write its trajectory");
    runCmd->add_option("scene", run.scene, "Scene file (JSON)")->required();
    addOverrideFlags(runCmd, run.overrides);
    addRunFlags(runCmd, run.run);
    runCmd->add_option("--out", run.out, "Trajectory file, .csv or .jsonl");
    runCmd->add_option("--every", run.every, "Write every K-th step (step 0 always)");
    runCmd->add_option("--metrics", run.metrics, "Summary file, .json");
    runCmd->add_option("--trace", run.trace,
                       "The OpenCL device's commands of every step, .json (Chrome trace events)");
    runCmd->add_flag("--quiet", run.quiet, "No progress bar");

    ValidateArgs validate;
    CLI::App* validateCmd = app.add_subcommand("validate", "Check a scene file and summarise it");
    validateCmd->add_option("scene", validate.scene, "Scene file (JSON)")->required();

    ViewArgs view;
    CLI::App* viewCmd = app.add_subcommand("view", "Open a window on a scene or a recorded run");
    addOverrideFlags(viewCmd, view.common.overrides);
    addRunFlags(viewCmd, view.common.run);
    addViewOptions(viewCmd, view);

    RenderArgs render;
    CLI::App* renderCmd =
        app.add_subcommand("render", "Draw a scene off-screen to PNG files or a video");
    addOverrideFlags(renderCmd, render.common.overrides);
    addRunFlags(renderCmd, render.common.run);
    addRenderOptions(renderCmd, render);

    SweepArgs sweep;
    CLI::App* sweepCmd = app.add_subcommand(
        "sweep", "Run a parameter sweep on Dask (needs the Python package: docs/python.md)");
    sweepCmd->add_option("sweep", sweep.file, "Sweep file (JSON, docs/python.md)")->required();
    sweepCmd->add_option("--workers", sweep.workers, "Workers of the local Dask cluster");
    sweepCmd->add_option("--scheduler", sweep.scheduler,
                         "A Dask scheduler (tcp://host:port) instead of a local cluster");
    sweepCmd->add_option("--out", sweep.out, "Write the table as CSV (default: stdout)");

    GpuCommands gpuCommands(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kExitOk : kExitBadInput;
    }
    deviceFromEnvironment(run.run);
    if (int code = kExitOk; gpuCommands.dispatch(code)) return code;
    if (runCmd->parsed()) return runCommand(run);
    if (validateCmd->parsed()) return validateCommand(validate);
    if (viewCmd->parsed()) return viewCommand(view);
    if (renderCmd->parsed()) return renderCommand(render);
    if (sweepCmd->parsed()) {
        sweepFromEnvironment(sweep);
        return sweepCommand(sweep);
    }
    return kExitBadInput;
}
