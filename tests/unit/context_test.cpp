// tests/unit/context_test.cpp: host/gpu/context: the work sizes the program is built with, from
// a device's reported limits; the split of a strided launch's items (rubble/shared/group.h).
#include "host/gpu/context.h"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

#include "rubble/shared/group.h"

namespace rubble {
namespace {

gpu::DeviceInfo device(std::uint32_t units, std::uint64_t maxGroup) {
    gpu::DeviceInfo d;
    d.computeUnits = units;
    d.maxWorkGroupSize = maxGroup;
    d.localMemory = 64 * 1024;
    return d;
}

TEST(WorkSizes, PoclsTwoCoresGetTheDefaults) {
    const gpu::WorkSizes w = gpu::workSizesFor(device(2, 4096));
    EXPECT_EQ(w.sortItems, 256u);
    EXPECT_EQ(w.sortItems, RUBBLE_SORT_ITEMS);
    EXPECT_EQ(w.broadGroup, 64u);
    EXPECT_EQ(w.pairGroup, 64u);
}

TEST(WorkSizes, ACpuDeviceTakesItsItemsInRunsAndAGpuOneGroupWidthApart) {
    gpu::DeviceInfo cpu = device(2, 4096), gpu = device(40, 1024);
    cpu.cpu = true;
    EXPECT_TRUE(gpu::workSizesFor(cpu).contiguousItems);
    EXPECT_FALSE(gpu::workSizesFor(gpu).contiguousItems);
}

TEST(WorkSizes, ALargeGpuGetsMoreSortItems) {
    // 40 units of 64 lanes: 2,560 work-items, rounded up to a power of two.
    EXPECT_EQ(gpu::workSizesFor(device(40, 1024)).sortItems, 4096u);
    EXPECT_EQ(gpu::workSizesFor(device(12, 1024)).sortItems, 1024u);
    // Never more than 4096 (the histogram's scan is one work-item).
    EXPECT_EQ(gpu::workSizesFor(device(200, 1024)).sortItems, 4096u);
    EXPECT_EQ(gpu::workSizesFor(device(0, 1024)).sortItems, 256u);
}

TEST(WorkSizes, GroupsFitTheDevicesLargestGroup) {
    EXPECT_EQ(gpu::workSizesFor(device(4, 32)).pairGroup, 32u);
    EXPECT_EQ(gpu::workSizesFor(device(4, 48)).broadGroup, 32u); // a power of two below it
    EXPECT_EQ(gpu::workSizesFor(device(4, 1)).pairGroup, 1u);
}

// The blocks of the PGS solve as the device suits: a GPU none; a CPU device its four per compute
// unit once the world has kPgsBlockBodies bodies for each, fewer below, one for a small world
// (which then sweeps in the CPU's order).
TEST(WorkSizes, ASmallWorldSolvesInFewerBlocks) {
    EXPECT_EQ(gpu::defaultPgsBlocks(0, 100000), 0u);
    EXPECT_EQ(gpu::defaultPgsBlocks(8, 16385), 8u);
    EXPECT_EQ(gpu::defaultPgsBlocks(8, 1025), 8u); // debris_1k
    EXPECT_EQ(gpu::defaultPgsBlocks(8, 3 * gpu::kPgsBlockBodies + 5), 3u);
    EXPECT_EQ(gpu::defaultPgsBlocks(8, 2 * gpu::kPgsBlockBodies - 1), 1u);
    EXPECT_EQ(gpu::defaultPgsBlocks(8, 211), 1u); // pyramid_20
    EXPECT_EQ(gpu::defaultPgsBlocks(8, 0), 1u);
}

TEST(WorkSizes, BuildOptionsDefineThem) {
    gpu::WorkSizes w;
    w.sortItems = 1024;
    w.broadGroup = 32;
    w.pairGroup = 16;
    const std::string o = gpu::buildOptionsFor(w);
    EXPECT_EQ(o.rfind(gpu::kBuildOptions, 0), 0u) << o;
    EXPECT_NE(o.find("-DRUBBLE_SORT_ITEMS=1024u"), std::string::npos) << o;
    EXPECT_NE(o.find("-DRUBBLE_GROUP_BROAD=32u"), std::string::npos) << o;
    EXPECT_NE(o.find("-DRUBBLE_GROUP_PAIRS=16u"), std::string::npos) << o;
    EXPECT_NE(o.find("-DRUBBLE_CONTIGUOUS_ITEMS=0"), std::string::npos) << o;
    w.contiguousItems = true;
    EXPECT_NE(gpu::buildOptionsFor(w).find("-DRUBBLE_CONTIGUOUS_ITEMS=1"), std::string::npos);
    // The joints' projection in float without fp64, in double (4 and 8 bytes of scratch) with.
    EXPECT_NE(o.find("-DRUBBLE_JOINT_DOUBLE=0"), std::string::npos) << o;
    EXPECT_EQ(w.jointRealBytes(), 4u);
    w.jointDouble = true;
    EXPECT_NE(gpu::buildOptionsFor(w).find("-DRUBBLE_JOINT_DOUBLE=1"), std::string::npos);
    EXPECT_EQ(w.jointRealBytes(), 8u);
}

// A strided launch's split of n items (itemRangeItem), both ways, for item counts around the
// launch's size (none, fewer than its work-items, a few per work-item, uneven): every item is
// taken by exactly one work-item; a group's items lie in one block of consecutive items, the
// groups' blocks in group order; with runs, each work-item's items are consecutive and follow
// the previous work-item's.
TEST(ItemRange, EveryItemOnceInItsGroupsBlock) {
    const std::uint32_t groups = 8, size = 4;
    for (const int contiguous : {0, 1})
        for (const std::uint32_t n : {0u, 1u, 5u, 31u, 32u, 33u, 100u, 257u, 1000u}) {
            std::vector<int> taken(n, 0);
            std::uint32_t lastGroupEnd = 0, lastItemEnd = 0;
            for (std::uint32_t g = 0; g < groups; ++g) {
                std::uint32_t lo = n, hi = 0, inGroup = 0;
                for (std::uint32_t k = 0; k < size; ++k) {
                    const shared::ItemRange r =
                        shared::itemRangeItem(n, groups, size, g, k, contiguous);
                    EXPECT_EQ(r.step, contiguous ? 1u : size);
                    if (contiguous && r.first < r.end) {
                        EXPECT_EQ(r.first, lastItemEnd) << "n " << n << " group " << g;
                        lastItemEnd = r.end;
                    }
                    for (std::uint32_t p = r.first; p < r.end; p += r.step) {
                        ASSERT_LT(p, n);
                        ++taken[p];
                        ++inGroup;
                        lo = std::min(lo, p);
                        hi = std::max(hi, p + 1);
                    }
                }
                if (lo < hi) {
                    EXPECT_EQ(hi - lo, inGroup) << "n " << n << " group " << g;
                    EXPECT_GE(lo, lastGroupEnd) << "n " << n << " group " << g;
                    lastGroupEnd = hi;
                }
            }
            for (std::uint32_t p = 0; p < n; ++p)
                EXPECT_EQ(taken[p], 1) << "item " << p << " of " << n << ", runs " << contiguous;
        }
}

} // namespace
} // namespace rubble
