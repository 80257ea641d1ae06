// tests/gpu/tuning_test.cpp: each tuning parameter of host/gpu/tuning.h at a value other than the
// device's default. A parameter that only shares out independent work (TuningEffect::Order)
// steps small scenes to the same bits as the default; one that changes float precision or the
// Gauss-Seidel order stays within a bound of it and keeps the physics (nothing sinks or flies).
// Each case builds at most one program of its own (PoCL caches it for the next run).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "gpu_fixture.h"
#include "host/gpu/tuning.h"

namespace rubble {
namespace {

using gpu::TuningEffect;
using gpu::TuningParameter;

// The value each parameter runs at here, from its default on this device: a count other than
// the default (a sort pass whose chunks hold several items even in a small scene, groups of a
// sixteenth of the default's, no serial tail, colors only or one block per few bodies), the
// other value of a flag.
std::uint32_t otherValue(std::string_view name, std::uint32_t value) {
    static const std::map<std::string_view, std::uint32_t (*)(std::uint32_t)> other = {
        {"sortItems", [](std::uint32_t) { return 7u; }},
        {"broadGroup", [](std::uint32_t v) { return std::max(1u, v / 16); }},
        {"pairGroup", [](std::uint32_t v) { return std::max(1u, v / 16); }},
        {"contiguousItems", [](std::uint32_t v) { return 1u - v; }},
        {"jointDouble", [](std::uint32_t v) { return 1u - v; }},
        {"pgsBlocks", [](std::uint32_t v) { return v == 0 ? 4u : 0u; }},
        {"pgsBlockBodies", [](std::uint32_t) { return 2u; }},
        {"serialElements", [](std::uint32_t v) { return v == 0 ? 1024u : 0u; }},
    };
    const auto it = other.find(name);
    return it == other.end() ? value : it->second(value);
}

const TuningParameter& parameterNamed(std::string_view name) {
    for (const TuningParameter& p : gpu::tuningParameters())
        if (p.name == name) return p;
    ADD_FAILURE() << "no tuning parameter " << name;
    return gpu::tuningParameters().front();
}

std::vector<std::string> namesWith(bool (*keep)(TuningEffect)) {
    std::vector<std::string> names;
    for (const TuningParameter& p : gpu::tuningParameters())
        if (keep(p.effect)) names.emplace_back(p.name);
    return names;
}

TEST(TuningTable, NamesEachParameterOnceAndBuildsFromItsDefines) {
    std::set<std::string_view> names, defines;
    gpu::WorkSizes sizes;
    for (const TuningParameter& p : gpu::tuningParameters()) {
        EXPECT_TRUE(names.insert(p.name).second) << p.name;
        EXPECT_FALSE(p.meaning.empty() || p.rule.empty() || p.chosenBy.empty()) << p.name;
        for (const bool cpu : {true, false}) {
            gpu::DeviceInfo device;
            device.cpu = device.fp64 = cpu;
            device.computeUnits = 4;
            device.maxWorkGroupSize = 1024;
            EXPECT_NE(otherValue(p.name, p.choose(device)), p.choose(device))
                << p.name << " has no other value in this test";
        }
        if (p.define.empty()) continue;
        EXPECT_TRUE(defines.insert(p.define).second) << p.define;
        sizes.*p.field = 3;
        const std::string option = " -D" + std::string(p.define) + "=3" + (p.flag ? "" : "u");
        EXPECT_NE(gpu::buildOptionsFor(sizes).find(option), std::string::npos) << option;
    }
    EXPECT_EQ(names.size(), 8u);
    EXPECT_EQ(defines.size(), 5u);
}

TEST(TuningTable, RefusesAValueTheDeviceCannotTake) {
    gpu::DeviceInfo device;
    device.maxWorkGroupSize = 32;
    const gpu::WorkSizes sizes;
    auto refused = [&](std::string_view name, std::uint32_t value) {
        const gpu::TuningValue v{name, value};
        Result<gpu::WorkSizes> r = gpu::tunedWorkSizes(sizes, std::span(&v, 1), device);
        if (r.ok()) return std::string("accepted");
        EXPECT_EQ(r.error().kind, ErrorKind::BadInput);
        EXPECT_EQ(r.error().where, "tuning " + std::string(name));
        return r.error().message;
    };
    EXPECT_NE(refused("groupSize", 8).find("pairGroup"), std::string::npos);
    EXPECT_NE(refused("pairGroup", 64).find("32"), std::string::npos);
    EXPECT_NE(refused("sortItems", 0).find("at least 1"), std::string::npos);
    EXPECT_NE(refused("jointDouble", 2).find("0 or 1"), std::string::npos);
    const gpu::TuningValue fine[] = {{"pairGroup", 32}, {"serialElements", 0}};
    Result<gpu::WorkSizes> r = gpu::tunedWorkSizes(sizes, fine, device);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->pairGroup, 32u);
    EXPECT_EQ(r->serialElements, 0u);
    EXPECT_EQ(r->broadGroup, sizes.broadGroup);
}

// One run: a scene of the source tree on the device (SAT when `sat`, else as the scene says)
// stepped `steps` times, deterministic (device rows sorted), with `blocks`
// (RunOptions::pgsBlocks) and each body sleeping by itself when `bodySleep`.
struct SceneRun {
    const char* scene;
    int steps;
    int blocks;
    bool bodySleep;
    bool sat;
};

// Between them every tuned kernel: SAT with PGS in the device's blocks and colored (the colors'
// launches and the serial tail; the split pass, a bounce, the layer pass, joints, an explosion),
// the SAT path's sleep kernels and carried still pairs, the particle path's grid sort with
// Jacobi and with PGS, a falling chain of ten links whose joints the projection holds, and
// pyramid_20's hundreds of pairs, more than a strided launch of small groups has work-items.
const SceneRun kRuns[] = {
    {"tests/oclgrind/small_sat.json", 40, -1, false, true},
    {"tests/oclgrind/small_sat.json", 40, 0, false, true},
    {"tests/oclgrind/small_sat_sleep.json", 18, -1, true, true},
    {"tests/oclgrind/small.json", 30, -1, false, false},
    {"tests/oclgrind/small_particle_pgs.json", 30, 0, false, false},
    {"scenes/chain.json", 60, -1, false, true},
    {"scenes/pyramid_20.json", 10, -1, false, true},
};

// Every body's state after every step.
using Trajectory = std::vector<std::vector<BodyState>>;

class Tuning : public test::GpuTest {
  protected:
    // A context built with `name` at its other value, the device's default for every other
    // parameter but the groups with contiguousItems: a strided launch whose work-items outnumber
    // the items gives each at most one whichever way it splits them, so that parameter runs
    // with groups of a sixteenth, fewer work-items than pyramid_20 has pairs.
    std::shared_ptr<gpu::Context> tunedContext(std::string_view name) {
        const gpu::WorkSizes& sizes = context()->workSizes();
        std::vector<gpu::TuningValue> values = {
            {name, otherValue(name, sizes.*parameterNamed(name).field)}};
        if (name == "contiguousItems")
            for (std::string_view group : {"broadGroup", "pairGroup"})
                values.push_back({group, otherValue(group, sizes.*parameterNamed(group).field)});
        Result<std::shared_ptr<gpu::Context>> c = gpu::Context::create(RunOptions{}, values);
        EXPECT_TRUE(c.ok()) << c.error().describe();
        return c.ok() ? *c : nullptr;
    }

    static Trajectory trajectory(const SceneRun& r, const std::shared_ptr<gpu::Context>& c) {
        Result<Scene> scene = loadScene(std::string(RUBBLE_SOURCE_DIR) + "/" + r.scene);
        EXPECT_TRUE(scene.ok()) << scene.error().describe();
        if (!scene.ok()) return {};
        scene->simulation.backend = Backend::OpenCl;
        if (r.sat) scene->simulation.collision.method = CollisionMethod::Sat;
        RunOptions run;
        run.context = c;
        run.deterministic = true;
        run.pgsBlocks = r.blocks;
        run.bodySleep = r.bodySleep;
        Result<World> world = World::create(*scene, run);
        EXPECT_TRUE(world.ok()) << world.error().describe();
        if (!world.ok()) return {};
        Trajectory t;
        for (int step = 0; step < r.steps; ++step) {
            const Status s = world->step();
            EXPECT_TRUE(s.ok()) << r.scene << " step " << step << ": " << s.error().describe();
            if (!s.ok()) break;
            std::vector<BodyState> bodies;
            for (std::uint32_t i = 0; i < world->bodyCount(); ++i) bodies.push_back(world->body(i));
            t.push_back(std::move(bodies));
        }
        return t;
    }
};

class OrderTuning : public Tuning, public ::testing::WithParamInterface<std::string> {};

TEST_P(OrderTuning, StepsEveryRunToTheDefaultsBits) {
    const std::shared_ptr<gpu::Context> tuned = tunedContext(GetParam());
    ASSERT_TRUE(tuned);
    for (const SceneRun& r : kRuns) {
        const Trajectory expected = trajectory(r, context()), got = trajectory(r, tuned);
        ASSERT_EQ(got.size(), std::size_t(r.steps)) << r.scene;
        ASSERT_EQ(expected.size(), got.size()) << r.scene;
        for (std::size_t step = 0; step < got.size(); ++step)
            for (std::size_t i = 0; i < got[step].size(); ++i)
                ASSERT_TRUE(test::sameBits(expected[step][i], got[step][i]))
                    << r.scene << " (blocks " << r.blocks << "), body " << i << " at step "
                    << step + 1;
    }
}

INSTANTIATE_TEST_SUITE_P(, OrderTuning, ::testing::ValuesIn(namesWith([](TuningEffect e) {
                             return e == TuningEffect::Order;
                         })),
                         [](const auto& param) { return param.param; });

// A parameter that changes float precision or the Gauss-Seidel order: every body ends each run
// within this distance of where the default leaves it, m. Float joints stay within 1e-4 m of
// the double projection over the chain's second of swinging; another order of Gauss-Seidel
// updates within 5 cm, pyramid_20's crates (1 m wide) landing on each other in its first steps
// and small_sat's bounces and explosion amplifying the difference most. A change that broke
// either path (a lost row or joint, a block sweeping bodies of another block) leaves a crate
// sunk or a link loose by far more: a crate falls 14 cm in pyramid_20's ten steps.
float boundFor(TuningEffect effect) {
    return effect == TuningEffect::Precision ? 1e-4f : 0.05f;
}

class NearTuning : public Tuning, public ::testing::WithParamInterface<std::string> {};

TEST_P(NearTuning, EndsEveryRunNearTheDefault) {
    const TuningParameter& p = parameterNamed(GetParam());
    if (p.field == &gpu::WorkSizes::jointDouble && !context()->device().fp64)
        GTEST_SKIP() << "the device has no fp64: the projection in double cannot build";
    const std::shared_ptr<gpu::Context> tuned = tunedContext(GetParam());
    ASSERT_TRUE(tuned);
    for (const SceneRun& r : kRuns) {
        const Trajectory expected = trajectory(r, context()), got = trajectory(r, tuned);
        ASSERT_EQ(got.size(), std::size_t(r.steps)) << r.scene;
        ASSERT_EQ(expected.size(), got.size()) << r.scene;
        float largest = 0.0f;
        for (std::size_t i = 0; i < got.back().size(); ++i) {
            const float apart = glm::distance(expected.back()[i].position, got.back()[i].position);
            ASSERT_TRUE(std::isfinite(apart)) << r.scene << ": body " << i;
            largest = std::max(largest, apart);
        }
        std::printf("[ %s ] %s (blocks %d): %.3g m from the default\n", GetParam().c_str(), r.scene,
                    r.blocks, largest);
        EXPECT_LE(largest, boundFor(p.effect)) << r.scene << " (blocks " << r.blocks << ")";
    }
}

INSTANTIATE_TEST_SUITE_P(, NearTuning, ::testing::ValuesIn(namesWith([](TuningEffect e) {
                             return e != TuningEffect::Order;
                         })),
                         [](const auto& param) { return param.param; });

} // namespace
} // namespace rubble
