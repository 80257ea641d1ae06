// tests/gpu/lcp_twin_test.cpp: OpenCL stage 5, dense variant (buildLcpRows, assembleDelassus,
// scaleLcpRows, CLBlast's SGEMV and projectLcp) against its CPU twin on one input, and the
// lcp-jacobi solver on the opencl backend against the cpu backend.
#include "gpu_fixture.h"
#include "host/gpu/integrate.h"
#include "host/dynamics/lcp_jacobi.h"
#include "host/gpu/lcp_jacobi.h"

namespace rubble {
namespace {

using namespace shared;

// A loose heap of 32 boxes and a ball on a floor (0.5 m particles, with friction): about a
// hundred contacts, three rows each; `frictionless` zeroes the materials' friction.
std::string heap(bool frictionless) {
    return R"({"format": "rubble-scene", "version": 1, "name": "heap",
      "simulation": {"dt": 0.016666667, "collision": {"method": "particles",
                     "particle_spacing": 0.5}, "solver": {"type": "lcp-jacobi", "iterations": 10}},
      "materials": {"default": {"friction": )" +
           std::string(frictionless ? "0" : "0.6") + R"(}},
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "ball": {"type": "sphere", "radius": 0.5}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true},
                 {"name": "ball", "shape": "ball", "mass": 2, "position": [0.3, 3.2, 0.2]}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [4, 2, 4],
                      "origin": [-1.6, 0.5, -1.6], "spacing": [1.05, 1.02, 1.05],
                      "rotation_jitter": 0.2, "seed": 4, "name_prefix": "c"}]})";
}

// A problem built on the host, for the device.
gpu::HostLcp hostLcp(const DenseLcp& p) {
    return {p.contacts, p.stride, p.matrix, p.rhs, p.inverseScale, p.friction, p.lambda};
}

// One step of the particle method's stages with the Jacobi solve, as the pipeline runs them,
// so that the rows built next have last step's contacts and impulses to warm-start from.
Status stepStages(test::DeviceStage& d, const StepParams& params) {
    gpu::StageQueue& q = d.q();
    gpu::ContactBuffers& k = d.collision.contacts();
    RUBBLE_TRY(q.resetStatus(k.capacity));
    RUBBLE_TRY(gpu::integrateVelocities(q, d.bodies, params.gravity, params.dt));
    RUBBLE_TRY(d.collision.transform(q, d.bodies));
    RUBBLE_TRY(d.collision.buildGrid(q, d.bodies, d.sort));
    RUBBLE_TRY(d.collision.collide(q));
    RUBBLE_TRY(d.collision.readCount(q));
    RUBBLE_TRY(d.jacobi.buildRows(q, d.bodies, k, d.collision.count(), params.rows, false));
    RUBBLE_TRY(
        d.jacobi.solve(q, d.bodies, k, params.solver.iterations, params.jacobiRelaxation));
    RUBBLE_TRY(gpu::integratePositions(q, d.bodies, params.dt, params.symplectic()));
    RUBBLE_TRY(d.collision.keepForWarmStart(q));
    k.previousCount = k.count;
    return q.finish();
}

class LcpTwin : public test::GpuTest {
  protected:
    // The device world's state after 30 steps on stages of its own, which step once (so that
    // its rows have last step's impulses to start from), then collide this step's contacts and
    // build their rows; the same rows and bodies on the host.
    void prepare(bool frictionless) {
        const std::string scene = heap(frictionless);
        World world = deviceWorld(scene);
        for (int i = 0; i < 30; ++i) ASSERT_TRUE(world.step().ok());
        stage_ = deviceStage(scene, &world);
        test::DeviceStage& d = *stage_;
        gpu::StageQueue& q = d.q();
        gpu::ContactBuffers& k = d.collision.contacts();
        const StepParams params = d.in.params(30);
        ASSERT_TRUE(stepStages(d, params).ok());
        ASSERT_TRUE(d.bodies.enqueueRead(q, s().view(), false).ok());
        ASSERT_TRUE(q.finish().ok());
        ASSERT_TRUE(d.collision.transform(q, d.bodies).ok());
        ASSERT_TRUE(d.collision.buildGrid(q, d.bodies, d.sort).ok());
        ASSERT_TRUE(q.resetStatus(k.capacity).ok());
        ASSERT_TRUE(d.collision.collide(q).ok());
        ASSERT_TRUE(d.collision.readCount(q).ok());
        ASSERT_TRUE(
            d.jacobi.buildRows(q, d.bodies, k, d.collision.count(), params.rows, true).ok());
        rows_ = d.read<ContactRow>(k.rows, k.count);
        ASSERT_GT(rows_.size(), 60u);
    }
    BodyArrays& s() { return stage_->in.bodies; }
    const gpu::Context& context() { return stage_->context(); }
    std::unique_ptr<test::DeviceStage> stage_;
    std::vector<ContactRow> rows_;
};

TEST_F(LcpTwin, TheDenseProblemMatchesCpu) {
    prepare(false);
    const gpu::DeviceBodies& b = stage_->bodies;
    const gpu::ContactBuffers& k = stage_->collision.contacts();
    const std::uint32_t stride = lcpStride(stage_->in.surfaces, s().masses);
    ASSERT_EQ(stride, 3u);
    gpu::LcpBuffers device;
    ASSERT_TRUE(gpu::buildLcpOnDevice(context(), k.rows, k.count, stride, b.velocities, b.masses,
                                      b.flags, b.poses, device)
                    .ok());
    DenseLcp cpu;
    buildLcpRows(rows_, s().velocities, s().masses, s().poses, stride, cpu);
    assembleDelassus(cpu);
    scaleLcpRows(cpu);
    std::vector<float> matrix, rhs, inverseScale, lambda;
    ASSERT_TRUE(gpu::downloadLcpProblem(context(), device, matrix, rhs, inverseScale).ok());
    ASSERT_TRUE(gpu::downloadLcpLambda(context(), device, lambda).ok());
    test::expectNearRel(matrix, cpu.matrix, 1e-5f);
    test::expectNearRel(rhs, cpu.rhs, 1e-5f);
    test::expectNearRel(inverseScale, cpu.inverseScale, 1e-5f);
    test::expectNearRel(lambda, cpu.lambda, 1e-5f);
}

// Relative 1e-5 against the larger of the two, so that impulses near zero compare absolutely.
void expectLambdaNear(const std::vector<float>& a, const std::vector<float>& b) {
    ASSERT_EQ(a.size(), b.size());
    float scale = 0.0f;
    for (float v : b) scale = std::max(scale, std::fabs(v));
    int failures = 0;
    for (std::size_t i = 0; i < a.size() && failures < 10; ++i)
        if (std::fabs(a[i] - b[i]) > 1e-5f * scale) {
            ADD_FAILURE() << "lambda[" << i << "]: " << a[i] << " vs " << b[i] << " (scale "
                          << scale << ")";
            ++failures;
        }
}

void iterateTwins(const gpu::Context& c, DenseLcp cpu, int iterations) {
    const float relaxation = 1.8f;
    gpu::LcpBuffers device;
    ASSERT_TRUE(gpu::uploadLcp(c, hostLcp(cpu), device).ok());
    ASSERT_TRUE(
        gpu::iterateLcpJacobi(c, device, iterations, relaxation, device.status).ok());
    solveLcpJacobi(cpu, iterations, relaxation);
    std::vector<float> lambda;
    ASSERT_TRUE(gpu::downloadLcpLambda(c, device, lambda).ok());
    expectLambdaNear(lambda, cpu.lambda);
}

TEST_F(LcpTwin, SolveLcpJacobiMatchesCpuWithFriction) {
    prepare(false);
    DenseLcp cpu;
    buildLcpRows(rows_, s().velocities, s().masses, s().poses, 3u, cpu);
    assembleDelassus(cpu);
    scaleLcpRows(cpu);
    ASSERT_GT(cpu.size(), 180u);
    iterateTwins(context(), cpu, 20);
}

TEST_F(LcpTwin, SolveLcpJacobiMatchesCpuFrictionless) {
    prepare(true);
    const std::uint32_t stride = lcpStride(stage_->in.surfaces, s().masses);
    ASSERT_EQ(stride, 1u);
    DenseLcp cpu;
    buildLcpRows(rows_, s().velocities, s().masses, s().poses, stride, cpu);
    assembleDelassus(cpu);
    scaleLcpRows(cpu);
    iterateTwins(context(), cpu, 20);
}

// SGEMV forms beta y with beta = 0: the product buffer is zeroed when the problem is uploaded,
// so that a NaN left in it cannot reach lambda (fmax(NaN, 0) would quietly make it 0).
TEST_F(LcpTwin, ANaNLeftInTheProductBufferDoesNotReachLambda) {
    prepare(true);
    const gpu::Context& c = context();
    DenseLcp cpu;
    buildLcpRows(rows_, s().velocities, s().masses, s().poses, 1u, cpu);
    assembleDelassus(cpu);
    scaleLcpRows(cpu);
    gpu::LcpBuffers device;
    ASSERT_TRUE(gpu::uploadLcp(c, hostLcp(cpu), device).ok());
    ASSERT_TRUE(
        gpu::fill(c, device.product, 0x7fc00000u, cpu.size() * sizeof(float)).ok());
    ASSERT_TRUE(gpu::uploadLcp(c, hostLcp(cpu), device).ok());
    ASSERT_TRUE(gpu::iterateLcpJacobi(c, device, 5, 1.8f, device.status).ok());
    solveLcpJacobi(cpu, 5, 1.8f);
    std::vector<float> lambda;
    ASSERT_TRUE(gpu::downloadLcpLambda(c, device, lambda).ok());
    expectLambdaNear(lambda, cpu.lambda);
}

} // namespace
} // namespace rubble
