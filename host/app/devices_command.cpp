// host/app/devices_command.cpp: `rubble devices`: the OpenCL devices by index, with
// --bandwidth the measured copy bandwidths and each kernel's achieved share of them; and the
// registration of the gpu subcommands (devices, compare, solvers).
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "host/app/commands.h"
#include "host/app/gpu_commands.h"
#include "host/gpu/context.h"
#include "host/gpu/device.h"
#include "host/gpu/traffic.h"
#include "rubble/scene.h"
#include "rubble/tools.h"
#include "rubble/world.h"

namespace rubble::app {

void deviceFromEnvironment(RunOptions& run) {
    if (!run.device.empty()) return;
    if (const char* d = std::getenv("RUBBLE_DEVICE")) run.device = d;
}

GpuCommands::GpuCommands(CLI::App& app) {
    devices_ = app.add_subcommand("devices", "List the OpenCL devices (--device takes the index "
                                             "or a part of the name; so does RUBBLE_DEVICE)");
    DevicesArgs& d = devicesArgs_;
    devices_->add_flag("--bandwidth", d.bandwidth,
                       "Measure the device's copy bandwidth, host<->device and host memcpy");
    devices_->add_option("--megabytes", d.megabytes, "Size of each measured copy, MiB");
    devices_->add_option("--repeats", d.repeats, "Copies of each kind (the median is reported)");
    devices_->add_option("--scene", d.scene,
                         "With --bandwidth: run this scene on the device (particles, jacobi) and "
                         "report each kernel's bytes/s against the copy bandwidth");
    devices_->add_option("--steps", d.steps, "Steps of the scene's run");
    addOverrideFlag(devices_, "particle-spacing", d.overrides);
    devices_->add_flag("--sat", d.sat,
                       "The scene's run collides with SAT and solves with PGS (every body on the "
                       "device) instead of particles and jacobi");
    devices_->add_flag("--pgs", d.pgs,
                       "The scene's run solves its particle contacts with PGS instead of jacobi")
        ->excludes("--sat");
    addRunFlag(devices_, "device", d.run);

    compare_ = app.add_subcommand(
        "compare", "Run a scene on two configurations and report their divergence step by step");
    CompareArgs& c = compareArgs_;
    compare_->add_option("scene", c.scene, "Scene file (JSON)")->required();
    compare_->add_option("--steps", c.steps, "Steps to compare");
    compare_
        ->add_option("--a", c.a,
                     "Settings of side a, KEY=VALUE (KEY: " + compareKeysText() + ")")
        ->required();
    compare_->add_option("--b", c.b, "Settings of side b, as --a")->required();
    compare_->add_option("--csv", c.csv, "Write the per-step table as CSV");
    compare_->add_option("--plot", c.plot, "Draw the table to a PNG (python3 with matplotlib)");
    addRunFlag(compare_, "device", c.run);
    addRunFlag(compare_, "kernel-dir", c.run);

    solvers_ = app.add_subcommand(
        "solvers", "Freeze one step's contacts and compare the solvers' convergence on them");
    SolversArgs& s = solversArgs_;
    solvers_->add_option("scene", s.scene, "Scene file (JSON)")->required();
    solvers_->add_option("--step", s.step, "Step whose contact set is frozen");
    solvers_->add_option("--iterations", s.iterations, "Iterations of each iterative solver");
    addOverrideFlag(solvers_, "collision", s.overrides);
    solvers_->add_option("--csv", s.csv, "Write the per-iteration table as CSV");
    solvers_->add_flag("--frictionless", s.frictionless,
                       "Set every material's friction to 0 (lemke solves frictionless sets)");
    solvers_->add_flag("--suite", s.suite,
                       "Run the solver test set instead: every scene of the folder (or the "
                       "scene) with every solver on every path, at equal constraint passes");
    solvers_->add_option("--steps", s.steps, "--suite: steps of each run");
    solvers_->add_option("--passes", s.passes,
                         "--suite: constraint passes per step (pgs iterations; soft-step "
                         "substeps x (1 + relax))");
    solvers_->add_option("--relax", s.relax, "--suite: soft step's relax passes per substep");
    solvers_->add_option("--paths", s.paths,
                         "--suite: cpu, device-colored, device-blocks (default all)")
        ->delimiter(',');
    addRunFlag(solvers_, "device", s.run);
    addRunFlag(solvers_, "kernel-dir", s.run);
}

bool GpuCommands::dispatch(int& exitCode) {
    if (devices_->parsed()) {
        deviceFromEnvironment(devicesArgs_.run);
        exitCode = devicesCommand(devicesArgs_);
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

namespace {

double gbps(double bytesPerSecond) { return bytesPerSecond * 1e-9; }

// Each kernel's device time over a run of the scene, its bytes (host/gpu/traffic.h) and their
// rate as a fraction of the device's copy bandwidth.
int kernelShares(const DevicesArgs& args, double deviceCopy) {
    Result<Scene> scene = loadScene(args.scene);
    if (!scene) return report(scene.error());
    SimulationOptions& sim = scene->simulation;
    sim.backend = Backend::OpenCl;
    sim.collision.method = args.sat ? CollisionMethod::Sat : CollisionMethod::Particles;
    sim.solver.type = args.sat || args.pgs ? SolverType::Pgs : SolverType::Jacobi;
    if (Status s = applyOverrides(args.overrides, *scene); !s) return report(s.error());
    Result<World> world = World::create(*scene, args.run);
    if (!world) return report(world.error());
    for (int i = 0; i < args.steps; ++i)
        if (Status s = world->step(); !s) return report(s.error());
    std::vector<DeviceCommandTime> kernels = world->deviceProfile();
    std::sort(kernels.begin(), kernels.end(),
              [](const DeviceCommandTime& a, const DeviceCommandTime& b) { return a.ms > b.ms; });
    if (args.sat)
        std::printf("\n%s, %d steps, sat and pgs: device time per step and bytes moved (each "
                    "element a kernel touches, once)\n",
                    args.scene.c_str(), args.steps);
    else
        std::printf("\n%s, %d steps, particle spacing %.2f m, %s: device time per step and "
                    "bytes moved (each element a kernel touches, once)\n",
                    args.scene.c_str(), args.steps, double(sim.collision.particleSpacing),
                    args.pgs ? "pgs" : "jacobi");
    std::printf("%-24s %10s %9s %12s %10s %9s\n", "kernel", "ms/step", "launches", "MB/launch",
                "GB/s", "of copy");
    double ms = 0, bytes = 0;
    for (const DeviceCommandTime& k : kernels) {
        const double perStep = k.ms / args.steps, seconds = k.ms * 1e-3;
        const double rate = seconds > 0 ? double(k.bytes) / seconds : 0.0;
        ms += perStep;
        bytes += double(k.bytes) / args.steps;
        std::printf("%-24s %10.3f %9.1f %12.3f %10.2f %8.1f%%\n", k.name.c_str(), perStep,
                    double(k.launches) / args.steps,
                    k.launches ? double(k.bytes) / double(k.launches) * 1e-6 : 0.0, gbps(rate),
                    100.0 * rate / deviceCopy);
    }
    const double rate = ms > 0 ? bytes / (ms * 1e-3) : 0.0;
    std::printf("%-24s %10.3f %9s %12.3f %10.2f %8.1f%%\n", "(all)", ms, "", bytes * 1e-6,
                gbps(rate), 100.0 * rate / deviceCopy);
    std::printf("bytes per step %.1f MB: %.2f ms at the device copy bandwidth\n", bytes * 1e-6,
                bytes / deviceCopy * 1e3);
    return kExitOk;
}

int bandwidthCommand(const DevicesArgs& args) {
    Result<std::shared_ptr<gpu::Context>> context = gpu::Context::create(args.run);
    if (!context) return report(context.error());
    const gpu::Context& c = **context;
    std::printf("device: %s\nprogram build (clBuildProgram): %.1f ms\n", c.describe().c_str(),
                c.buildMs());
    const std::uint64_t bytes = std::uint64_t(std::max(args.megabytes, 1)) << 20;
    Result<gpu::Bandwidth> b = gpu::measureBandwidth(c, bytes, args.repeats);
    if (!b) return report(b.error());
    std::printf("copies of %llu MiB, median of %d (a copy counts its bytes read and written)\n",
                static_cast<unsigned long long>(bytes >> 20), std::max(args.repeats, 1));
    std::printf("%-34s %8.2f GB/s\n", "device copy (clEnqueueCopyBuffer)", gbps(b->deviceCopy));
    std::printf("%-34s %8.2f GB/s\n", "host to device (clEnqueueWrite)", gbps(b->hostToDevice));
    std::printf("%-34s %8.2f GB/s\n", "device to host (clEnqueueRead)", gbps(b->deviceToHost));
    std::printf("%-34s %8.2f GB/s\n", "host memcpy", gbps(b->hostMemcpy));
    if (args.scene.empty()) return kExitOk;
    return kernelShares(args, b->deviceCopy);
}

} // namespace

int devicesCommand(const DevicesArgs& args) {
    if (args.bandwidth) return bandwidthCommand(args);
    Result<std::vector<DeviceDesc>> devices = openClDevices();
    if (!devices) return report(devices.error());
    for (const DeviceDesc& d : *devices)
        std::printf("%u: %s (platform %s; %s; driver %s; %u compute units, %.1f GiB)\n", d.index,
                    d.name.c_str(), d.platform.c_str(), d.version.c_str(), d.driver.c_str(),
                    d.computeUnits, double(d.globalMemory) / (1024.0 * 1024.0 * 1024.0));
    return kExitOk;
}

} // namespace rubble::app
