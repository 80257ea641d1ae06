// tests/gpu/memory_test.cpp: the device memory ledger (host/gpu/memory.h): buffers counted as
// they are made and freed, and a buffer past the device's largest allocation or the process's
// address space refused before the OpenCL call, the old buffer kept.
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "gpu_fixture.h"
#include "host/gpu/memory.h"
#include "host/gpu/pairs.h"
#include "host/gpu/stage_queue.h"

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

// The ledger lists each live buffer by the call that made it, the largest first; a buffer
// grown is listed once at its new size, a buffer freed not at all.
TEST_F(DeviceMemory, BuffersAreListedByTheCallThatMadeThem) {
    const gpu::Context& c = *context();
    const auto listed = [&](const std::string& where) {
        std::vector<std::uint64_t> sizes;
        for (const gpu::BufferRecord& r : gpu::deviceBuffers(c.context()))
            if (r.where.ends_with(where)) sizes.push_back(r.bytes);
        return sizes;
    };
    {
        gpu::Buffer a, b;
        ASSERT_TRUE(a.reserve(c.context(), 1 << 20).ok());
        const std::string aWhere = "memory_test.cpp:" + std::to_string(__LINE__ - 1);
        ASSERT_TRUE(b.reserve(c.context(), 3 << 20).ok());
        const std::string bWhere = "memory_test.cpp:" + std::to_string(__LINE__ - 1);
        EXPECT_EQ(listed(aWhere), std::vector<std::uint64_t>{1u << 20});
        EXPECT_EQ(listed(bWhere), std::vector<std::uint64_t>{3u << 20});
        ASSERT_TRUE(a.reserve(c.context(), 5 << 20).ok());
        const std::string grownWhere = "memory_test.cpp:" + std::to_string(__LINE__ - 1);
        EXPECT_TRUE(listed(aWhere).empty());
        EXPECT_EQ(listed(grownWhere), std::vector<std::uint64_t>{5u << 20});
        const std::vector<gpu::BufferRecord> all = gpu::deviceBuffers(c.context());
        for (std::size_t i = 1; i < all.size(); ++i) EXPECT_GE(all[i - 1].bytes, all[i].bytes);
        b = gpu::Buffer();
        EXPECT_TRUE(listed(bWhere).empty());
    }
    for (const gpu::BufferRecord& r : gpu::deviceBuffers(c.context()))
        EXPECT_EQ(r.where.find("memory_test.cpp"), std::string::npos) << r.where;
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

// A CPU device's buffers live in the process's memory: under an address-space limit a little
// above what the process holds, a buffer that would pass it is refused with ErrorKind::Limit
// naming RLIMIT_AS, before the OpenCL runtime tries (and, in PoCL, aborts).
TEST_F(DeviceMemory, ABufferPastTheAddressSpaceLimitIsRefused) {
    const gpu::Context& c = *context();
    if (!c.device().cpu) GTEST_SKIP() << "the device's buffers are not host memory";
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    ASSERT_NE(f, nullptr);
    unsigned long long pages = 0;
    ASSERT_EQ(std::fscanf(f, "%llu", &pages), 1);
    std::fclose(f);
    const std::uint64_t used = pages * std::uint64_t(sysconf(_SC_PAGESIZE));
    rlimit old{};
    ASSERT_EQ(getrlimit(RLIMIT_AS, &old), 0);
    rlimit tight = old;
    tight.rlim_cur = used + (std::uint64_t(512) << 20);
    ASSERT_EQ(setrlimit(RLIMIT_AS, &tight), 0);
    gpu::Buffer big, small;
    const Status refused = big.reserve(c.context(), std::size_t(1) << 30);
    const Status fits = small.reserve(c.context(), std::size_t(1) << 20);
    ASSERT_EQ(setrlimit(RLIMIT_AS, &old), 0);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().kind, ErrorKind::Limit);
    EXPECT_NE(refused.error().message.find("RLIMIT_AS"), std::string::npos)
        << refused.error().describe();
    EXPECT_EQ(big.bytes(), 0u);
    EXPECT_TRUE(fits.ok()) << fits.error().describe();
}

// The pair sets hold impulses by the contact points their pairs keep, not four slots per pair in
// each set: 2^20 pair slots of SAT (both sets, the candidates, the manifolds and the per-pair
// words) with room for an impulse per pair take at most 480 bytes a slot (four slots a pair
// took 728).
TEST_F(DeviceMemory, APairSlotHoldsNoImpulsesOfItsOwn) {
    Result<std::unique_ptr<gpu::StageQueue>> q = gpu::StageQueue::create(context());
    ASSERT_TRUE(q.ok()) << q.error().describe();
    const cl_context c = context()->context();
    const std::uint64_t before = gpu::deviceBytesInUse(c);
    constexpr std::uint32_t kSlots = 1u << 20;
    {
        gpu::PairStore pairs;
        const Status made = pairs.create(**q, kSlots, false);
        ASSERT_TRUE(made.ok()) << made.error().describe();
        EXPECT_GE(pairs.current.impulseRoom, kSlots);
        const std::uint64_t perSlot = (gpu::deviceBytesInUse(c) - before) / kSlots;
        EXPECT_LE(perSlot, 480u);
        ASSERT_TRUE((*q)->finish().ok());
    }
    EXPECT_EQ(gpu::deviceBytesInUse(c), before);
}

} // namespace
} // namespace rubble
