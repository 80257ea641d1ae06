// tests/gpu/particles_twin_test.cpp: OpenCL stages 2 to 5 (transformParticles, buildGrid,
// collideParticles, buildJacobiRows and solveJacobi) against their CPU twins on one input: a
// pile of boxes and balls after 40 steps, sizes that are not multiples of the group size.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <tuple>

#include "gpu_fixture.h"
#include "host/collision/grid.h"
#include "host/collision/particles.h"
#include "host/dynamics/jacobi.h"

namespace rubble {
namespace {

using namespace shared;

// 101 bodies (boxes and balls, 0.25 m particles) in a loose heap over a floor and a static box,
// solved by `solver`.
std::string heap(const std::string& solver = "jacobi") {
    return R"({"format": "rubble-scene", "version": 1, "name": "heap",
      "simulation": {"dt": 0.016666667, "collision": {"method": "particles",
                     "particle_spacing": 0.25}, "solver": {"type": ")" +
           solver + R"("}},
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "ball": {"type": "sphere", "radius": 0.4},
                 "slab": {"type": "box", "half_extents": [2, 0.25, 2]}},
      "bodies": [{"name": "floor", "shape": "floor", "static": true},
                 {"name": "slab", "shape": "slab", "static": true, "position": [3, 0.25, 0]}],
      "generators": [{"type": "grid", "shape": "crate", "mass": 1, "count": [5, 4, 4],
                      "origin": [-2, 1, -2], "spacing": [1.05, 1.05, 1.05],
                      "rotation_jitter": 0.3, "seed": 3, "name_prefix": "c"},
                     {"type": "grid", "shape": "ball", "mass": 1, "count": [1, 1, 19],
                      "origin": [3, 2, -4], "spacing": [1, 1, 0.9], "name_prefix": "b"}]})";
}

class ParticlesTwin : public test::GpuTest {
  protected:
    void SetUp() override {
        test::GpuTest::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;
        stepped_.emplace(deviceWorld(heap()));
        for (int i = 0; i < 40; ++i) ASSERT_TRUE(stepped_->step().ok());
        // The device's state after 40 steps, on a pipeline of its own: the shared input.
        stage_ = deviceStage(heap(), &*stepped_);
        world_.assign(set().particles.size(), float4{});
    }
    test::StageInput& in() { return stage_->in; }
    BodyArrays& s() { return stage_->in.bodies; }
    const ParticleSet& set() { return stage_->particles; }
    test::DeviceStage& d() { return *stage_; }
    template <class T> std::vector<T> read(const gpu::Buffer& b, std::size_t n) {
        return stage_->read<T>(b, n);
    }
    /// The device's contacts and the CPU twin's on the stage's particles at the fixture's state,
    /// each sorted by (particleA, featureB).
    void collideBoth(test::DeviceStage& stage, std::vector<ParticleContact>& device,
                     std::vector<ParticleContact>& cpu) {
        const ParticleSet& set = stage.particles;
        world_.assign(set.particles.size(), float4{});
        transformParticles(set.particles, s().poses, world_);
        ASSERT_TRUE(gpu::upload(stage.context(), stage.collision.world(),
                                std::span<const float4>(world_))
                        .ok());
        ASSERT_TRUE(stage.collision.buildGrid(stage.q(), stage.bodies, stage.sort).ok());
        ASSERT_TRUE(stage.q().resetStatus(stage.collision.contacts().capacity).ok());
        ASSERT_TRUE(stage.collision.collide(stage.q()).ok());
        ASSERT_TRUE(stage.collision.readCount(stage.q()).ok());
        buildGrid(world_, set.cellSize, set.bits, grid_);
        collideParticles(set, world_, grid_, s().masses, cpu);
        device = stage.read<ParticleContact>(stage.collision.contacts().contacts,
                                             stage.collision.contacts().count);
        // Device order is the atomics'; compare as sets, keyed by the two features.
        auto byKey = [](const ParticleContact& x, const ParticleContact& y) {
            return std::tie(x.particleA, x.featureB) < std::tie(y.particleA, y.featureB);
        };
        std::sort(device.begin(), device.end(), byKey);
        std::sort(cpu.begin(), cpu.end(), byKey);
    }
    /// The same contacts, field by field (the floats within 1e-5 relative).
    static void expectSameContacts(const std::vector<ParticleContact>& device,
                                   const std::vector<ParticleContact>& cpu) {
        ASSERT_EQ(device.size(), cpu.size());
        std::vector<float4> dp, cp;
        for (std::size_t i = 0; i < cpu.size(); ++i) {
            ASSERT_EQ(device[i].particleA, cpu[i].particleA) << i;
            ASSERT_EQ(device[i].featureB, cpu[i].featureB) << i;
            EXPECT_EQ(device[i].a, cpu[i].a);
            EXPECT_EQ(device[i].b, cpu[i].b);
            dp.push_back(device[i].point), dp.push_back(device[i].normal);
            cp.push_back(cpu[i].point), cp.push_back(cpu[i].normal);
        }
        test::expectNearRel(dp, cp, 1e-5f);
    }

    std::optional<World> stepped_; ///< the device world after 40 steps
    std::unique_ptr<test::DeviceStage> stage_;
    std::vector<float4> world_; ///< the CPU twin's particle positions
    ParticleGrid grid_;         ///< the CPU twin's grid
};

TEST_F(ParticlesTwin, TransformParticlesMatchesCpu) {
    ASSERT_NE(set().particles.size() % RUBBLE_GROUP_PARTICLES, 0u);
    ASSERT_TRUE(d().collision.transform(d().q(), d().bodies).ok());
    transformParticles(set().particles, s().poses, world_);
    test::expectNearRel(read<float4>(d().collision.world(), world_.size()), world_, 1e-5f);
}

TEST_F(ParticlesTwin, BuildGridMatchesCpu) {
    transformParticles(set().particles, s().poses, world_);
    // The same world positions on both sides, so that no particle changes cell by round-off.
    ASSERT_TRUE(
        gpu::upload(d().context(), d().collision.world(), std::span<const float4>(world_)).ok());
    ASSERT_TRUE(d().collision.buildGrid(d().q(), d().bodies, d().sort).ok());
    buildGrid(world_, set().cellSize, set().bits, grid_);
    const std::size_t n = world_.size();
    EXPECT_EQ(read<std::uint32_t>(d().collision.cellKeys(), n), grid_.keys);
    EXPECT_EQ(read<std::uint32_t>(d().collision.cellOrder(), n), grid_.order);
    // The device keeps, per cell, the first slot of a key at least the cell's; an empty cell
    // starts where the next one does.
    const std::vector<std::uint32_t> first =
        read<std::uint32_t>(d().collision.cellFirst(), grid_.cellStart.size() + 1);
    std::vector<std::uint32_t> start(grid_.cellStart.size()), end(grid_.cellEnd.size());
    for (std::size_t k = 0; k < start.size(); ++k) {
        const bool empty = first[k] == first[k + 1];
        start[k] = empty ? RUBBLE_EMPTY_CELL : first[k];
        end[k] = empty ? RUBBLE_EMPTY_CELL : first[k + 1];
    }
    EXPECT_EQ(start, grid_.cellStart);
    EXPECT_EQ(end, grid_.cellEnd);
}

TEST_F(ParticlesTwin, RadixSortSortsStablyAnyCount) {
    // 1000 keys with many repeats, not a multiple of the sort's item count.
    std::vector<std::uint32_t> keys(1000), values(1000);
    for (std::uint32_t i = 0; i < keys.size(); ++i) {
        keys[i] = (i * 2654435761u) >> 20;
        values[i] = i;
    }
    gpu::Buffer k, v, ka, va;
    const gpu::Context& c = d().context();
    ASSERT_TRUE(gpu::upload(c, k, std::span<const std::uint32_t>(keys)).ok());
    ASSERT_TRUE(gpu::upload(c, v, std::span<const std::uint32_t>(values)).ok());
    ASSERT_TRUE(ka.reserve(c.context(), 4000).ok());
    ASSERT_TRUE(va.reserve(c.context(), 4000).ok());
    ASSERT_TRUE(d().sort.sort(d().q(), k, v, ka, va, 1000, 12).ok());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> expected;
    for (std::uint32_t i = 0; i < keys.size(); ++i) expected.push_back({keys[i], i});
    std::stable_sort(expected.begin(), expected.end(),
                     [](auto x, auto y) { return x.first < y.first; });
    const std::vector<std::uint32_t> sortedKeys = read<std::uint32_t>(k, 1000);
    const std::vector<std::uint32_t> sortedValues = read<std::uint32_t>(v, 1000);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        ASSERT_EQ(sortedKeys[i], expected[i].first) << i;
        ASSERT_EQ(sortedValues[i], expected[i].second) << i;
    }
}

TEST_F(ParticlesTwin, CollideParticlesGivesTheSameContactSet) {
    std::vector<ParticleContact> device, cpu;
    ASSERT_NO_FATAL_FAILURE(collideBoth(*stage_, device, cpu));
    ASSERT_GT(cpu.size(), 100u);
    for (const ParticleContact& c : cpu) ASSERT_GT(c.point.w, 0.0f); // jacobi: overlaps only
    expectSameContacts(device, cpu);
}

// With PGS the contacts reach kParticleContactMargin further (gaps, negative depths) over a grid
// of wider cells: the twins agree on them, and the overlapping ones are the Jacobi set's (the
// same bodies, points and depths; PGS numbers a shape's particles in another order).
TEST_F(ParticlesTwin, CollideParticlesWithPgsMarginAddsTheGapsAndKeepsTheOverlaps) {
    auto pgs = deviceStage(heap("pgs"), &*stepped_);
    ASSERT_EQ(pgs->particles.margin, kParticleContactMargin);
    ASSERT_EQ(pgs->particles.cellSize, set().cellSize + kParticleContactMargin);
    std::vector<ParticleContact> device, cpu, jacobiDevice, jacobi;
    ASSERT_NO_FATAL_FAILURE(collideBoth(*pgs, device, cpu));
    expectSameContacts(device, cpu);
    ASSERT_NO_FATAL_FAILURE(collideBoth(*stage_, jacobiDevice, jacobi));
    using Touch = std::tuple<std::uint32_t, std::uint32_t, float, float, float, float>;
    auto touch = [](const ParticleContact& c) {
        return Touch{c.a, c.b, c.point.x, c.point.y, c.point.z, c.point.w};
    };
    std::vector<Touch> overlaps, expected;
    std::size_t gaps = 0;
    for (const ParticleContact& c : cpu) {
        EXPECT_GT(c.point.w, -kParticleContactMargin);
        if (c.point.w > 0.0f)
            overlaps.push_back(touch(c));
        else
            ++gaps;
    }
    for (const ParticleContact& c : jacobi) expected.push_back(touch(c));
    std::sort(overlaps.begin(), overlaps.end());
    std::sort(expected.begin(), expected.end());
    std::printf("[ heap ] %zu overlaps, %zu gaps within the margin\n", overlaps.size(), gaps);
    EXPECT_GT(gaps, 0u);
    EXPECT_EQ(overlaps, expected);
}

// PGS numbers a shape's particles in a scattered order (Gauss-Seidel sweeps a pair's contacts
// in particle order), the Jacobi solvers in the voxeliser's rows: the same particles, body by
// body, in another order.
TEST_F(ParticlesTwin, PgsParticlesAreTheJacobiOnesScattered) {
    auto pgs = deviceStage(heap("pgs"), &*stepped_);
    const std::vector<Particle>& a = set().particles;
    const std::vector<Particle>& b = pgs->particles.particles;
    ASSERT_EQ(a.size(), b.size());
    auto key = [](const Particle& p) {
        return std::tuple(p.body, p.offset.x, p.offset.y, p.offset.z, p.offset.w);
    };
    std::vector<decltype(key(a[0]))> ka, kb;
    std::size_t moved = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ka.push_back(key(a[i]));
        kb.push_back(key(b[i]));
        EXPECT_EQ(a[i].body, b[i].body) << i; // still grouped by body, in body order
        moved += key(a[i]) != key(b[i]) ? 1u : 0u;
    }
    std::sort(ka.begin(), ka.end());
    std::sort(kb.begin(), kb.end());
    EXPECT_EQ(ka, kb);
    EXPECT_GT(moved, a.size() / 2);
}

TEST_F(ParticlesTwin, JacobiRowsAndOneSweepMatchCpu) {
    transformParticles(set().particles, s().poses, s().masses, world_);
    buildGrid(world_, set().cellSize, set().bits, grid_);
    std::vector<ParticleContact> contacts;
    collideParticles(set(), world_, grid_, s().masses, contacts);
    sortContactsByParticle(contacts);
    ASSERT_GT(contacts.size(), 100u);
    ASSERT_TRUE(d().collision.uploadContacts(d().q(), contacts).ok());
    const SolverParams params = in().params().rows;
    gpu::ContactBuffers& k = d().collision.contacts();
    ASSERT_TRUE(
        d().jacobi.buildRows(d().q(), d().bodies, k, d().collision.count(), params, false).ok());
    JacobiState j;
    buildBodyLists(contacts, s().masses, j);
    std::vector<float4> warm(contacts.size(), vec4(0, 0, 0));
    buildJacobiRows(contacts, s().poses, s().velocities, s().masses, in().surfaces, params, warm,
                    j);
    const std::size_t n = contacts.size();
    EXPECT_EQ(read<std::uint32_t>(k.bodyStart, s().count() + 1), j.bodyStart);
    EXPECT_EQ(read<std::uint32_t>(k.bodyList, j.bodyList.size()), j.bodyList);
    test::expectNearRel(read<shared::ContactRow>(k.rows, n), j.rows, 1e-5f);

    // One sweep and its gather: the single-stage tolerance; ten: a looser one, as float
    // differences from the device's math library grow through the iterations.
    ASSERT_TRUE(d().jacobi.solve(d().q(), d().bodies, k, 1, 1.0f).ok());
    std::vector<BodyVelocity> before = s().velocities;
    solveJacobi(j, before, s().masses, s().poses, s().velocities, 1, 1.0f);
    test::expectNearRel(read<BodyVelocity>(d().bodies.velocities, s().count()),
                        s().velocities, 1e-5f);
    test::expectNearRel(read<shared::ContactRow>(k.rows, n), j.rows, 1e-5f);
}

// A contact buffer too small for the step grows, and the stages from collision on run again:
// the step ends as one that had room from the start, to the bit.
TEST_F(ParticlesTwin, ContactOverflowGrowsTheBuffersAndStepsTheSameBits) {
    const StepParams params = in().params(40);
    std::vector<BodyPose> poses[2];
    std::vector<BodyVelocity> velocities[2];
    for (int run = 0; run < 2; ++run) {
        Result<gpu::PipelineHandle> made = test::pipelineOf(
            context(), in(), &set(), CollisionMethod::Particles, run == 0 ? 10u : 0u);
        ASSERT_TRUE(made.ok()) << made.error().describe();
        gpu::Pipeline& p = **made;
        StepStats stats;
        ASSERT_TRUE(p.beginStep(params, gpu::StepInputs{}).ok());
        const Status met = p.endStep(params, in().names, stats);
        ASSERT_TRUE(met.ok()) << met.error().describe();
        EXPECT_GT(stats.deviceContactCount, 10u);
        BodyArrays out = in().bodies;
        ASSERT_TRUE(p.downloadBodies(out.view()).ok());
        poses[run] = out.poses;
        velocities[run] = out.velocities;
    }
    ASSERT_EQ(poses[0].size(), poses[1].size());
    EXPECT_EQ(std::memcmp(poses[0].data(), poses[1].data(), poses[0].size() * sizeof(BodyPose)), 0);
    EXPECT_EQ(std::memcmp(velocities[0].data(), velocities[1].data(),
                          velocities[0].size() * sizeof(BodyVelocity)),
              0);
}

} // namespace
} // namespace rubble
