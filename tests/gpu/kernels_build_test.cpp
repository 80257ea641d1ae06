// tests/gpu/kernels_build_test.cpp: the embedded program builds, every kernel in it is in the
// dispatch table with the same argument names in the same order (-cl-kernel-arg-info), and a
// kernel folder that does not build fails with its build log.
#include <filesystem>
#include <set>
#include <sstream>

#include "gpu_fixture.h"
#include "host/gpu/cl_check.h"
#include "host/gpu/kernel_table.h"

namespace rubble {
namespace {

class KernelsBuild : public test::GpuTest {};

std::string argName(cl_kernel k, cl_uint i) {
    std::size_t size = 0;
    if (clGetKernelArgInfo(k, i, CL_KERNEL_ARG_NAME, 0, nullptr, &size) != CL_SUCCESS) return "?";
    std::string s(size, '\0');
    clGetKernelArgInfo(k, i, CL_KERNEL_ARG_NAME, size, s.data(), nullptr);
    while (!s.empty() && s.back() == '\0') s.pop_back();
    return s;
}

TEST_F(KernelsBuild, EveryKernelMatchesItsDispatchSignature) {
    const gpu::Context& c = *context();
    for (const gpu::KernelSignature& sig : gpu::kernelSignatures()) {
        cl_kernel k = c.kernel(sig.id);
        ASSERT_NE(k, nullptr) << sig.name;
        cl_uint count = 0;
        ASSERT_EQ(clGetKernelInfo(k, CL_KERNEL_NUM_ARGS, sizeof count, &count, nullptr),
                  CL_SUCCESS);
        ASSERT_EQ(count, sig.args.size()) << sig.name;
        for (cl_uint i = 0; i < count; ++i)
            EXPECT_EQ(argName(k, i), sig.args[i]) << sig.name << " argument " << i;
    }
}

TEST_F(KernelsBuild, TheProgramHasNoKernelOutsideTheTable) {
    const gpu::Context& c = *context();
    std::size_t size = 0;
    ASSERT_EQ(clGetProgramInfo(c.program(), CL_PROGRAM_KERNEL_NAMES, 0, nullptr, &size), CL_SUCCESS);
    std::string names(size, '\0');
    ASSERT_EQ(clGetProgramInfo(c.program(), CL_PROGRAM_KERNEL_NAMES, size, names.data(), nullptr),
              CL_SUCCESS);
    names.resize(names.find('\0') == std::string::npos ? names.size() : names.find('\0'));
    std::set<std::string> inProgram, inTable;
    std::stringstream list(names);
    for (std::string n; std::getline(list, n, ';');) inProgram.insert(n);
    for (const gpu::KernelSignature& sig : gpu::kernelSignatures()) inTable.insert(std::string(sig.name));
    EXPECT_EQ(inProgram, inTable);
}

TEST_F(KernelsBuild, TheProgramIsBuiltWithTheDevicesWorkSizes) {
    const gpu::Context& c = *context();
    std::size_t size = 0;
    ASSERT_EQ(clGetProgramBuildInfo(c.program(), c.device().id, CL_PROGRAM_BUILD_OPTIONS, 0,
                                    nullptr, &size),
              CL_SUCCESS);
    std::string options(size, '\0');
    ASSERT_EQ(clGetProgramBuildInfo(c.program(), c.device().id, CL_PROGRAM_BUILD_OPTIONS, size,
                                    options.data(), nullptr),
              CL_SUCCESS);
    while (!options.empty() && options.back() == '\0') options.pop_back();
    // The options come from the tuning table (host/gpu/tuning.h), each -D parameter once.
    EXPECT_EQ(options, gpu::buildOptionsFor(c.workSizes()));
    EXPECT_NE(options.find("-DRUBBLE_SORT_ITEMS=" + std::to_string(c.workSizes().sortItems) + "u"),
              std::string::npos)
        << options;
    const gpu::WorkSizes expected = gpu::workSizesFor(c.device());
    for (const gpu::TuningParameter& p : gpu::tuningParameters())
        EXPECT_EQ(c.workSizes().*p.field, expected.*p.field) << p.name;
    // Every kernel of the SAT path takes its group on this device.
    for (const gpu::KernelId id : {gpu::KernelId::CollideShapes, gpu::KernelId::FindCellPairs}) {
        std::size_t most = 0;
        ASSERT_EQ(clGetKernelWorkGroupInfo(c.kernel(id), c.device().id, CL_KERNEL_WORK_GROUP_SIZE,
                                           sizeof most, &most, nullptr),
                  CL_SUCCESS);
        EXPECT_GE(most, c.workSizes().pairGroup) << gpu::signatureOf(id).name;
    }
}

TEST_F(KernelsBuild, TheKernelFolderOfTheSourceTreeBuildsLikeTheEmbeddedText) {
    RunOptions run;
    run.kernelDir = std::string(RUBBLE_SOURCE_DIR) + "/kernels";
    Result<std::string> fromDisk = gpu::programSource(run);
    ASSERT_TRUE(fromDisk.ok()) << fromDisk.error().describe();
    Result<std::string> embedded = gpu::programSource(RunOptions{});
    ASSERT_TRUE(embedded.ok());
    EXPECT_EQ(*fromDisk, *embedded);
}

TEST_F(KernelsBuild, AKernelThatFailsToBuildReturnsItsBuildLog) {
    const std::string dir = test::tempDir("broken_kernels");
    std::filesystem::copy(std::string(RUBBLE_SOURCE_DIR) + "/kernels", dir,
                          std::filesystem::copy_options::recursive);
    test::writeText(dir + "/zz_broken.cl",
                    "#include \"rubble/shared/body.h\"\n"
                    "__kernel void broken(__global float* x) {\n"
                    "    x[0] = undeclaredThing;\n"
                    "}\n");
    RunOptions run;
    run.kernelDir = dir;
    Result<std::shared_ptr<gpu::Context>> c = gpu::Context::create(run);
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().kind, ErrorKind::Device);
    EXPECT_EQ(c.error().where, "clBuildProgram");
    EXPECT_NE(c.error().message.find("build log"), std::string::npos) << c.error().message;
    EXPECT_NE(c.error().message.find("undeclaredThing"), std::string::npos) << c.error().message;
    EXPECT_NE(c.error().message.find("zz_broken.cl"), std::string::npos) << c.error().message;
}

TEST_F(KernelsBuild, AMissingKernelFolderIsBadInput) {
    RunOptions run;
    run.kernelDir = "/nonexistent/kernels";
    Result<std::shared_ptr<gpu::Context>> c = gpu::Context::create(run);
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().kind, ErrorKind::BadInput);
    EXPECT_NE(c.error().where.find("--kernel-dir"), std::string::npos);
}

TEST_F(KernelsBuild, ABadDeviceNameSaysWhichDevicesThereAre) {
    RunOptions run;
    run.device = "no-such-device-xyz";
    Result<std::shared_ptr<gpu::Context>> c = gpu::Context::create(run);
    ASSERT_FALSE(c.ok());
    EXPECT_EQ(c.error().kind, ErrorKind::BadInput);
    EXPECT_EQ(c.error().where, "--device");
    EXPECT_NE(c.error().message.find(context()->device().name), std::string::npos);
    const test::CommandResult r = test::runRubble(
        "run " + std::string(RUBBLE_SOURCE_DIR) +
        "/scenes/bench/debris_1k.json --steps 1 --backend opencl --collision particles "
        "--solver jacobi --device no-such-device-xyz");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--device"), std::string::npos) << r.output;
}

TEST_F(KernelsBuild, RubbleDevicesListsTheDevice) {
    const test::CommandResult r = test::runRubble("devices");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find(context()->device().name), std::string::npos) << r.output;
}

// `rubble devices --bandwidth --scene` sets the kernels of the path it is asked for against the
// copy bandwidth: particles with jacobi by default, with --pgs the particle contacts' PGS
// (particlePairs, solvePgs) and no Jacobi rows; --pgs with --sat is refused. (40 steps: the
// first crates land on debris_1k between steps 30 and 40.)
TEST_F(KernelsBuild, RubbleDevicesBandwidthRunsThePathItIsAskedFor) {
    const std::string run = "devices --bandwidth --megabytes 4 --repeats 2 --steps 40 --scene " +
                            std::string(RUBBLE_SOURCE_DIR) + "/scenes/bench/debris_1k.json";
    const test::CommandResult jacobi = test::runRubble(run);
    ASSERT_EQ(jacobi.exitCode, 0) << jacobi.output;
    EXPECT_NE(jacobi.output.find("solveJacobiRows"), std::string::npos) << jacobi.output;
    EXPECT_EQ(jacobi.output.find("particlePairs"), std::string::npos) << jacobi.output;
    const test::CommandResult pgs = test::runRubble(run + " --pgs");
    ASSERT_EQ(pgs.exitCode, 0) << pgs.output;
    for (const char* kernel : {"particlePairs", "contactKeys", "solvePgs"})
        EXPECT_NE(pgs.output.find(kernel), std::string::npos) << kernel << "\n" << pgs.output;
    EXPECT_EQ(pgs.output.find("solveJacobiRows"), std::string::npos) << pgs.output;
    const test::CommandResult both = test::runRubble(run + " --pgs --sat");
    EXPECT_EQ(both.exitCode, 2) << both.output;
    EXPECT_NE(both.output.find("excludes"), std::string::npos) << both.output;
}

TEST_F(KernelsBuild, ErrorsNameTheCallAndTheCode) {
    const Error e = gpu::clError("(m = clCreateBuffer(ctx, 0, 0, nullptr, &err), err)",
                                 CL_INVALID_BUFFER_SIZE);
    EXPECT_EQ(e.where, "clCreateBuffer");
    EXPECT_NE(e.message.find("CL_INVALID_BUFFER_SIZE (-61)"), std::string::npos) << e.message;
    EXPECT_EQ(e.kind, ErrorKind::Device);
}

} // namespace
} // namespace rubble
