// tests/gpu/layout_test.cpp: every shared struct has the same size and field offsets on the
// device as on the host (kernels/layout.cl measures them).
#include <cstddef>
#include <vector>

#include "gpu_fixture.h"
#include "rubble/shared/layout.h"

namespace rubble {
namespace {



struct Measure {
    std::vector<std::string> names;
    std::vector<std::uint32_t> values;
};

Measure hostLayout() {
    Measure m;
#define RUBBLE_HOST_SIZE(T)                                                                        \
    m.names.push_back("sizeof(" #T ")");                                                           \
    m.values.push_back(std::uint32_t(sizeof(shared::T)));
#define RUBBLE_HOST_OFFSET(T, f)                                                                   \
    m.names.push_back("offsetof(" #T ", " #f ")");                                                 \
    m.values.push_back(std::uint32_t(offsetof(shared::T, f)));
    RUBBLE_SHARED_LAYOUT(RUBBLE_HOST_SIZE, RUBBLE_HOST_OFFSET)
#undef RUBBLE_HOST_SIZE
#undef RUBBLE_HOST_OFFSET
    return m;
}

class Layout : public test::GpuTest {};

TEST_F(Layout, EverySharedStructMatchesTheDevice) {
    const Measure host = hostLayout();
    gpu::Buffer out;
    const gpu::Context& c = *context();
    ASSERT_TRUE(out.reserve(c.context(), host.values.size() * sizeof(cl_uint)).ok());
    const Status ran = gpu::Dispatch(c, gpu::KernelId::MeasureLayout).arg(out).run(1, 1);
    ASSERT_TRUE(ran.ok()) << ran.error().describe();
    std::vector<std::uint32_t> device(host.values.size());
    ASSERT_TRUE(gpu::download(c, out, std::span(device)).ok());
    for (std::size_t i = 0; i < host.values.size(); ++i)
        EXPECT_EQ(device[i], host.values[i]) << host.names[i];
    // The sizes written above the structs.
    EXPECT_EQ(sizeof(shared::Particle), 32u);
    EXPECT_EQ(sizeof(shared::ContactRow), 128u);
    EXPECT_EQ(sizeof(shared::HullShape), 112u);
    EXPECT_EQ(sizeof(shared::HullEdge), 80u);
    EXPECT_EQ(sizeof(shared::ContactManifold), 112u);
    EXPECT_EQ(sizeof(shared::PairCache), 96u);
    EXPECT_EQ(sizeof(shared::BodyBox), 32u);
    EXPECT_EQ(sizeof(shared::BodyPairRecord), 8u);
}

} // namespace
} // namespace rubble
