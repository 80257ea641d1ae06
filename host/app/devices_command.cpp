// host/app/devices_command.cpp: `rubble devices`: the OpenCL devices by index, and the
// registration of the gpu subcommands (devices, compare, solvers).
#include <cstdio>
#include <cstdlib>

#include "host/app/commands.h"
#include "host/app/gpu_commands.h"
#include "host/gpu/device.h"

namespace rubble::app {

void deviceFromEnvironment(RunOptions& run) {
    if (!run.device.empty()) return;
    if (const char* d = std::getenv("RUBBLE_DEVICE")) run.device = d;
}

GpuCommands::GpuCommands(CLI::App& app) {
    devices_ = app.add_subcommand("devices", "List the OpenCL devices (--device takes the index "
                                             "or a part of the name; so does RUBBLE_DEVICE)");

    compare_ = app.add_subcommand(
        "compare", "Run a scene on two configurations and report their divergence step by step");
    CompareArgs& c = compareArgs_;
    compare_->add_option("scene", c.scene, "Scene file (JSON)")->required();
    compare_->add_option("--steps", c.steps, "Steps to compare");
    compare_->add_option("--a", c.a,
                         "Settings of side a: backend=, collision=, solver=, iterations=, "
                         "integrator=, particle_spacing=, dt=, deterministic=")
        ->required();
    compare_->add_option("--b", c.b, "Settings of side b, as --a")->required();
    compare_->add_option("--csv", c.csv, "Write the per-step table as CSV");
    compare_->add_option("--plot", c.plot, "Draw the table to a PNG (python3 with matplotlib)");
    compare_->add_option("--device", c.run.device, "OpenCL device: a name fragment or an index");
    compare_->add_option("--kernel-dir", c.run.kernelDir, "Load kernels/*.cl from this folder");

    solvers_ = app.add_subcommand(
        "solvers", "Freeze one step's contacts and compare the solvers' convergence on them");
    SolversArgs& s = solversArgs_;
    solvers_->add_option("scene", s.scene, "Scene file (JSON)")->required();
    solvers_->add_option("--step", s.step, "Step whose contact set is frozen");
    solvers_->add_option("--iterations", s.iterations, "Iterations of each iterative solver");
    solvers_->add_option("--collision", s.collision, "sat or particles (default: the scene's)");
    solvers_->add_option("--csv", s.csv, "Write the per-iteration table as CSV");
    solvers_->add_flag("--frictionless", s.frictionless,
                       "Set every material's friction to 0 (lemke solves frictionless sets)");
    solvers_->add_option("--device", s.run.device, "OpenCL device: a name fragment or an index");
    solvers_->add_option("--kernel-dir", s.run.kernelDir, "Load kernels/*.cl from this folder");
}

bool GpuCommands::dispatch(int& exitCode) {
    if (devices_->parsed()) {
        exitCode = devicesCommand();
        return true;
    }
    if (compare_->parsed()) {
        deviceFromEnvironment(compareArgs_.run);
        exitCode = compareCommand(compareArgs_);
        return true;
    }
    if (solvers_->parsed()) {
        deviceFromEnvironment(solversArgs_.run);
        exitCode = solversCommand(solversArgs_);
        return true;
    }
    return false;
}

int devicesCommand() {
    Result<std::vector<gpu::DeviceInfo>> devices = gpu::listDevices();
    if (!devices) return report(devices.error());
    for (const gpu::DeviceInfo& d : *devices)
        std::printf("%u: %s (platform %s; %s; driver %s; %u compute units, %.1f GiB)\n", d.index,
                    d.name.c_str(), d.platform.c_str(), d.version.c_str(), d.driver.c_str(),
                    d.computeUnits, double(d.globalMemory) / (1024.0 * 1024.0 * 1024.0));
    return kExitOk;
}

} // namespace rubble::app
