// tests/unit/limits_test.cpp: host/core/limits: the step budgets, and the contact cap that
// follows the memory the process may use.
#include "host/core/limits.h"

#include <sys/resource.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace rubble {
namespace {

TEST(Limits, ContactCapIsHalfTheMemoryAtAKilobyteAPoint) {
    constexpr std::uint64_t kGiB = std::uint64_t(1) << 30;
    // 24 GiB: 12 GiB of points of 1 KiB.
    EXPECT_EQ(contactCap(24 * kGiB), std::size_t(12) << 20);
    EXPECT_EQ(contactCap(4 * kGiB), std::size_t(2) << 20);
    // A tiny limit still admits the floor every budget allows.
    EXPECT_EQ(contactCap(1 << 20), kBudgetFloor);
}

TEST(Limits, ContactBudgetGrowsWithTheBodiesUpToTheCap) {
    EXPECT_EQ(contactBudget(0), kBudgetFloor);
    EXPECT_EQ(contactBudget(1000), kBudgetFloor + 64 * 1000);
    // A resting pile of 10^6 crates (about 12 points each) fits where memory allows it.
    const std::size_t cap = contactCap(usableMemory());
    EXPECT_EQ(contactBudget(std::size_t(1) << 30), cap);
    EXPECT_EQ(contactBudget(1'000'000), std::min(kBudgetFloor + 64 * 1'000'000, cap));
}

TEST(Limits, UsableMemoryIsAtMostThePhysicalMemoryAndTheAddressSpaceLimit) {
    const std::uint64_t physical =
        std::uint64_t(sysconf(_SC_PHYS_PAGES)) * std::uint64_t(sysconf(_SC_PAGESIZE));
    EXPECT_GT(usableMemory(), 0u);
    EXPECT_LE(usableMemory(), physical);
    rlimit limit{};
    ASSERT_EQ(getrlimit(RLIMIT_AS, &limit), 0);
    if (limit.rlim_cur != RLIM_INFINITY) {
        EXPECT_LE(usableMemory(), limit.rlim_cur);
    }
}

} // namespace
} // namespace rubble
