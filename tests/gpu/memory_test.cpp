// tests/gpu/memory_test.cpp: the device memory ledger (host/gpu/memory.h): buffers counted as
// they are made and freed, a buffer past the device's largest allocation refused before the
// OpenCL call, and a world that does not fit the process's address space stopped with exit 4
// and the stage named, not an abort inside the OpenCL runtime.
#include <string>

#include "gpu_fixture.h"
#include "host/gpu/memory.h"

namespace rubble {
namespace {

class DeviceMemory : public test::GpuTest {};

TEST_F(DeviceMemory, BuffersAreCountedWhileTheyLive) {
    const gpu::Context& c = *context();
    const std::uint64_t before = gpu::deviceBytesInUse(c.context());
    {
        gpu::Buffer a, b;
        ASSERT_TRUE(a.reserve(c.context(), 1 << 20).ok());
        ASSERT_TRUE(b.reserve(c.context(), 3 << 20).ok());
        EXPECT_EQ(gpu::deviceBytesInUse(c.context()), before + (4u << 20));
        // Growing replaces the buffer: the old bytes leave the count.
        ASSERT_TRUE(a.reserve(c.context(), 2 << 20).ok());
        EXPECT_EQ(gpu::deviceBytesInUse(c.context()), before + (5u << 20));
        gpu::Buffer moved = std::move(b);
        EXPECT_EQ(gpu::deviceBytesInUse(c.context()), before + (5u << 20));
        EXPECT_GE(gpu::deviceBytesPeak(c.context()), before + (5u << 20));
    }
    EXPECT_EQ(gpu::deviceBytesInUse(c.context()), before);
}

TEST_F(DeviceMemory, ABufferPastTheLargestAllocationIsRefusedAndTheOldOneKept) {
    const gpu::Context& c = *context();
    const std::uint64_t largest = c.device().maxAllocation;
    ASSERT_GT(largest, 0u);
    gpu::Buffer b;
    ASSERT_TRUE(b.reserve(c.context(), 4096).ok());
    const std::vector<std::uint32_t> words(1024, 7u);
    ASSERT_TRUE(gpu::upload(c, b, std::span<const std::uint32_t>(words)).ok());
    const Status refused = b.reserve(c.context(), std::size_t(largest) + 1);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().kind, ErrorKind::Limit);
    EXPECT_NE(refused.error().message.find("CL_DEVICE_MAX_MEM_ALLOC_SIZE"), std::string::npos)
        << refused.error().describe();
    EXPECT_EQ(b.bytes(), 4096u);
    Result<std::vector<std::uint32_t>> kept = gpu::download<std::uint32_t>(c, b, 1024);
    ASSERT_TRUE(kept.ok());
    EXPECT_EQ(*kept, words);
}

// A CPU device's buffers live in the process's memory: under an address-space limit that the
// runtime starts in but a 64k-crate pile's buffers do not fit, the run stops with exit 4 naming
// the device memory, the stage and RLIMIT_AS.
TEST_F(DeviceMemory, AWorldPastTheAddressSpaceLimitExitsFour) {
    if (!context()->device().cpu) GTEST_SKIP() << "the device's buffers are not host memory";
    const std::string scene = std::string(RUBBLE_SOURCE_DIR) + "/scenes/bench/debris_64k.json";
    const test::CommandResult r = test::runShell(
        "ulimit -v 3000000 && " + std::string(RUBBLE_BINARY) + " run " + scene +
        " --backend opencl --collision sat --steps 2 --quiet");
    EXPECT_EQ(r.exitCode, 4) << r.output;
    EXPECT_NE(r.output.find("device memory"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("RLIMIT_AS"), std::string::npos) << r.output;
}

} // namespace
} // namespace rubble
