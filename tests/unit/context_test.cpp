// tests/unit/context_test.cpp: host/gpu/context: the work sizes the program is built with, from
// a device's reported limits.
#include "host/gpu/context.h"

#include <gtest/gtest.h>

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
}

} // namespace
} // namespace rubble
