// tests/gpu/sat_twin_test.cpp: the SAT method on the device against its CPU twin
// (SatCollision): the narrow phase on thousands of random shape pairs over three steps (the
// feature cache included), the broad phase on hundreds of bodies of every kind, a pair overflow,
// and a resting stack whose feature ids stay put on both.
#include <algorithm>
#include <map>
#include <random>

#include "gpu_fixture.h"
#include "host/collision/sat_collision.h"
#include "support/pair_cases.h"

namespace rubble {
namespace {

// Why two manifolds differ, or empty when they agree: the same point count and feature ids,
// normals within 1e-4, depths within 1e-5 m, positions within 1e-4 m.
std::string difference(const Manifold* cpu, const shared::ContactManifold& d) {
    const std::uint32_t count = cpu ? cpu->count : 0u;
    if (count != d.count)
        return "point count " + std::to_string(count) + " vs " + std::to_string(d.count);
    if (count == 0) return {};
    const glm::vec3 normal(d.normal.x, d.normal.y, d.normal.z);
    if (glm::any(glm::greaterThan(glm::abs(normal - cpu->normal), glm::vec3(1e-4f))))
        return "normal differs by " + std::to_string(glm::length(normal - cpu->normal));
    for (std::uint32_t i = 0; i < count; ++i) {
        const ContactPoint& p = cpu->points[i];
        const shared::float4 q = d.points[i];
        if (p.feature != d.features[i])
            return "point " + std::to_string(i) + ": feature " + std::to_string(p.feature) +
                   " vs " + std::to_string(d.features[i]);
        if (std::fabs(p.depth - q.w) > 1e-5f)
            return "point " + std::to_string(i) + ": depth " + std::to_string(p.depth) + " vs " +
                   std::to_string(q.w);
        if (glm::length(p.position - glm::vec3(q.x, q.y, q.z)) > 1e-4f)
            return "point " + std::to_string(i) + ": position differs";
    }
    return {};
}

class SatTwin : public test::GpuTest {
  protected:
    std::unique_ptr<test::DeviceStage> satStageOf(const test::StageInput& in) {
        return satStage(in);
    }
};

// 4,000 pairs (boxes, random hulls, spheres, planes; touching, gaps within the margin, deep,
// crossed edges, apart), three steps each: as placed, moved by up to 0.3 mm (the cached feature
// is reused), moved by up to 5 mm (the full test, last step's feature first).
TEST_F(SatTwin, NarrowPhaseMatchesTheCpuOnRandomPairs) {
    // More pairs than the launch has work-items on a two-core device (2 x 32 groups of 64), so
    // that each work-group goes through its block of pairs (blockFirst, blockEnd) in rounds.
    test::PairCases cases = test::makePairCases(20240611u, 9000);
    test::StageInput& in = cases.in;
    std::unique_ptr<test::DeviceStage> device = satStageOf(in);
    test::DeviceStage& p = *device;
    SatCollision cpu(ContactForm::Manifolds);
    const StepParams params = in.params();
    std::vector<BodyPair> pairs;
    for (std::uint32_t i = 0; i < cases.kinds.size(); ++i) pairs.push_back({2 * i, 2 * i + 1});
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> sym(-1.0f, 1.0f);
    int compared = 0, withContacts = 0, mismatches = 0;
    std::map<std::string, int> byKind;
    int featureKinds[4] = {0, 0, 0, 0}; // points by kind: face of a, face of b, edges, primitive
    for (int step = 0; step < 3; ++step) {
        if (step > 0) {
            const float move = step == 1 ? 0.0003f : 0.005f;
            for (std::size_t b = 1; b < in.bodies.count(); b += 2) {
                shared::BodyPose& pose = in.bodies.poses[b];
                if (in.bodies.isStatic(std::uint32_t(b))) continue;
                pose.position.x += move * sym(rng);
                pose.position.y += move * sym(rng);
                pose.orientation.z += move * sym(rng);
                pose.orientation = shared::quatNormalize(pose.orientation);
            }
            ASSERT_TRUE(p.uploadBodies(in.bodies.view()).ok());
        }
        StepContacts out;
        // The broad phase runs for its per-body reach; its pairs are replaced by the cases'. The
        // cases' planes meet every body, more pairs than its budget: that refusal comes after
        // the reach.
        const Status found = cpu.broadPhase(in.collisionScene(), in.bodies.view(), params, out);
        ASSERT_TRUE(found.ok() || found.error().kind == ErrorKind::Limit)
            << found.error().describe();
        out.pairs = pairs;
        ASSERT_TRUE(cpu.narrowPhase(in.collisionScene(), in.bodies.view(), params, out).ok());

        ASSERT_TRUE(p.computeAabbs(params.dt).ok());
        ASSERT_TRUE(p.uploadPairs(pairs).ok());
        ASSERT_TRUE(p.narrowPhase(params.dt).ok());
        Result<std::vector<shared::ContactManifold>> manifolds = p.downloadManifolds();
        ASSERT_TRUE(manifolds.ok());
        ASSERT_EQ(manifolds->size(), pairs.size());
        Result<gpu::DeviceStatus> status = p.readStatus();
        ASSERT_TRUE(status.ok());

        std::size_t k = 0;
        for (std::size_t i = 0; i < pairs.size(); ++i) {
            const shared::ContactManifold& d = (*manifolds)[i];
            EXPECT_EQ(d.a, pairs[i].a);
            EXPECT_EQ(d.b, pairs[i].b);
            const Manifold* m = nullptr;
            if (k < out.manifolds.size() && out.manifolds[k].a == pairs[i].a &&
                out.manifolds[k].b == pairs[i].b)
                m = &out.manifolds[k++];
            ++compared;
            withContacts += m != nullptr;
            ++byKind[test::toString(cases.kinds[i])];
            for (std::uint32_t q = 0; q < d.count; ++q) ++featureKinds[d.features[q] >> 30];
            const std::string why = difference(m, d);
            if (why.empty()) continue;
            ++mismatches;
            if (mismatches <= 10)
                ADD_FAILURE() << "step " << step << ", pair " << i << " ("
                              << test::toString(cases.kinds[i]) << ", shapes "
                              << in.bodies.shapeOf[pairs[i].a] << " and "
                              << in.bodies.shapeOf[pairs[i].b] << "): " << why;
        }
        EXPECT_EQ(k, out.manifolds.size());
        EXPECT_EQ(status->contacts, out.contactCount) << "step " << step;
        EXPECT_FLOAT_EQ(status->largestPenetration, out.largestPenetration) << "step " << step;
        ASSERT_TRUE(p.keepPairFeatures().ok());
    }
    std::string kinds;
    for (const auto& [kind, n] : byKind) kinds += " " + kind + " " + std::to_string(n) + ",";
    std::printf("[ narrow phase twin ] %d pair steps, %d with contacts, %d mismatched, 0 "
                "excluded;%s points: %d face of a, %d face of b, %d edge-edge, %d primitive\n",
                compared, withContacts, mismatches, kinds.c_str(), featureKinds[0], featureKinds[1],
                featureKinds[2], featureKinds[3]);
    // No near-tie is excluded: the device's arithmetic is the reference's, operation for
    // operation, so even a tie between two axes is broken the same way.
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(withContacts, compared / 2);
    EXPECT_GT(featureKinds[2], 500); // the edge query and edge contacts are exercised
}

// A scene of every kind of body for the broad phase: crates, slabs, spheres and random hulls of
// mixed sizes, moving in every direction (the reach grows their boxes), some static, some
// asleep, a large static slab and a large crate (too large for the grid's cells), two planes,
// and joined pairs.
test::StageInput broadPhaseScene(std::uint32_t seed, int count, bool withJoints) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
    test::StageInput in;
    in.scene.materials.push_back(MaterialDesc{});
    auto add = [&](const ShapeDesc& d) {
        Result<Shape> s = buildShape(d);
        if (!s) test::abortOn(s.error());
        in.shapes.push_back(std::move(*s));
        return std::uint32_t(in.shapes.size() - 1);
    };
    auto box = [&](glm::vec3 h) {
        ShapeDesc d;
        d.type = ShapeType::Box;
        d.halfExtents = h;
        d.where = "box";
        return add(d);
    };
    std::vector<std::uint32_t> small = {box(glm::vec3(0.5f)), box({0.6f, 0.2f, 0.4f})};
    for (float r : {0.3f, 0.6f}) {
        ShapeDesc d;
        d.type = ShapeType::Sphere;
        d.radius = r;
        d.where = "ball";
        small.push_back(add(d));
    }
    for (int i = 0; i < 3; ++i) {
        in.shapes.push_back(test::randomHull(rng));
        small.push_back(std::uint32_t(in.shapes.size() - 1));
    }
    const std::uint32_t slab = box({15.0f, 0.5f, 15.0f}), big = box(glm::vec3(2.5f));
    ShapeDesc planeDesc;
    planeDesc.type = ShapeType::Plane;
    planeDesc.where = "plane";
    const std::uint32_t plane = add(planeDesc);

    auto body = [&](std::uint32_t shape, glm::vec3 at, bool isStatic) {
        BodyDesc b;
        b.name = "body " + std::to_string(in.names.size());
        b.shape = shape;
        b.isStatic = isStatic;
        b.mass = 1.0f;
        b.position = at;
        b.orientation = test::randomRotation(rng);
        if (!isStatic) {
            b.linearVelocity = test::randomDirection(rng) * (6.0f * unit(rng) * unit(rng));
            b.angularVelocity = test::randomDirection(rng) * (3.0f * unit(rng));
        }
        in.scene.bodies.push_back(b);
        appendBodyArrays(in.bodies, b, in.shapes[shape]);
        in.names.push_back(b.name);
    };
    body(plane, {0.0f, -0.4f, 0.0f}, true);
    body(slab, {0.0f, -0.5f, 0.0f}, true);
    for (int i = 0; i < count; ++i) {
        const glm::vec3 at(9.0f * sym(rng), 4.0f * unit(rng), 9.0f * sym(rng));
        const std::uint32_t shape =
            small[std::uniform_int_distribution<std::size_t>(0, small.size() - 1)(rng)];
        body(shape, at, unit(rng) < 0.1f);
        if (unit(rng) < 0.1f) in.bodies.masses.back().flags |= RUBBLE_BODY_ASLEEP;
    }
    body(big, {2.0f, 2.0f, -1.0f}, false);
    // A tilted plane along one side.
    body(plane, {7.0f, 0.0f, 0.0f}, true);
    in.bodies.poses.back().orientation =
        toFloat4(glm::angleAxis(glm::radians(80.0f), glm::vec3(0, 0, 1)));
    if (withJoints)
        for (std::uint32_t i = 2; i + 1 < in.bodies.count() && in.joined.size() < 40; i += 7)
            in.joined.push_back({i, i + 1});
    in.surfaces = bodySurfaces(in.scene.materials, in.bodies.materialOf);
    return in;
}

// The device's pairs for the input's bodies, and the CPU's.
struct BothPairs {
    std::vector<BodyPair> device, cpu;
    std::vector<shared::BodyBox> deviceBoxes;
    std::vector<Aabb> cpuBoxes;
};

BothPairs findBoth(test::DeviceStage& p, SatCollision& cpu, const test::StageInput& in) {
    BothPairs r;
    const StepParams params = in.params();
    EXPECT_TRUE(p.uploadBodies(in.bodies.view()).ok());
    EXPECT_TRUE(p.resetStatus().ok());
    EXPECT_TRUE(p.broadPhase(params.dt).ok());
    Result<std::uint32_t> count = p.readPairCount();
    EXPECT_TRUE(count.ok());
    Result<std::vector<BodyPair>> pairs = p.downloadPairs();
    EXPECT_TRUE(pairs.ok());
    if (pairs.ok()) r.device = *pairs;
    Result<std::vector<shared::BodyBox>> boxes = p.downloadBoxes();
    EXPECT_TRUE(boxes.ok());
    if (boxes.ok()) r.deviceBoxes = *boxes;
    StepContacts out;
    EXPECT_TRUE(cpu.broadPhase(in.collisionScene(), in.bodies.view(), params, out).ok());
    r.cpu = out.pairs;
    r.cpuBoxes = cpu.cache().boxes;
    return r;
}

// 800 bodies over three steps (moved by their velocities in between): the same boxes, and the
// same pairs in the same (sorted) order.
TEST_F(SatTwin, BroadPhaseMatchesTheCpu) {
    test::StageInput in = broadPhaseScene(5, 800, true);
    std::unique_ptr<test::DeviceStage> device = satStageOf(in);
    SatCollision cpu(ContactForm::Manifolds);
    const float dt = in.params().dt;
    std::size_t total = 0;
    for (int step = 0; step < 3; ++step) {
        const BothPairs both = findBoth(*device, cpu, in);
        ASSERT_FALSE(both.cpu.empty());
        EXPECT_EQ(both.device, both.cpu)
            << "step " << step << ": " << both.device.size() << " pairs on the device, "
            << both.cpu.size() << " on the CPU";
        // Every body's box (a plane's holds its plane instead).
        for (std::uint32_t i = 0; i < in.bodies.count(); ++i) {
            if (in.shapes[in.bodies.shapeOf[i]].type == ShapeType::Plane) continue;
            const shared::BodyBox& d = both.deviceBoxes[i];
            const Aabb& c = both.cpuBoxes[i];
            EXPECT_EQ(glm::vec3(d.min.x, d.min.y, d.min.z), c.min) << "body " << i;
            EXPECT_EQ(glm::vec3(d.max.x, d.max.y, d.max.z), c.max) << "body " << i;
        }
        // What the pairs must hold: planes, large bodies, no two inactive, none joined.
        std::size_t planePairs = 0, slabPairs = 0, bigPairs = 0;
        for (const BodyPair& pair : both.cpu) {
            planePairs += pair.a == 0 || pair.b == in.bodies.count() - 1;
            slabPairs += pair.a == 1;
            bigPairs += pair.b == in.bodies.count() - 2 || pair.a == in.bodies.count() - 2;
            EXPECT_FALSE(std::binary_search(in.joined.begin(), in.joined.end(), pair));
        }
        EXPECT_GT(planePairs, 10u);
        EXPECT_GT(slabPairs, 10u);
        EXPECT_GT(bigPairs, 2u);
        total += both.cpu.size();
        for (std::uint32_t i = 0; i < in.bodies.count(); ++i) {
            shared::BodyPose& pose = in.bodies.poses[i];
            pose.position =
                shared::add4(pose.position, shared::scale4(in.bodies.velocities[i].linear, dt));
        }
    }
    std::printf("[ broad phase twin ] %u bodies, %zu pairs over 3 steps\n", in.bodies.count(),
                total);
}

// The columns sweep along the axis where the boxes spread most: the same scene stretched along
// each axis in turn (and, last, squeezed to a sheet one crate thick), so that each is the sweep
// axis once, finds the CPU's pairs: an entry's sweep stops at the first entry of its column that
// starts past its end, and no pair may be lost to the stop or to the choice of axis.
TEST_F(SatTwin, BroadPhaseMatchesTheCpuWhicheverAxisIsSwept) {
    const glm::vec3 stretches[] = {
        {4.0f, 1.0f, 0.25f}, {0.25f, 6.0f, 0.25f}, {0.25f, 1.0f, 4.0f}, {1.0f, 0.0f, 1.0f}};
    for (const glm::vec3& stretch : stretches) {
        test::StageInput in = broadPhaseScene(17, 600, true);
        for (std::uint32_t i = 2; i + 2 < in.bodies.count(); ++i) {
            shared::float4& at = in.bodies.poses[i].position;
            at = shared::vec4(at.x * stretch.x, at.y * stretch.y, at.z * stretch.z);
        }
        std::unique_ptr<test::DeviceStage> device = satStageOf(in);
        SatCollision cpu(ContactForm::Manifolds);
        const BothPairs both = findBoth(*device, cpu, in);
        ASSERT_GT(both.cpu.size(), 100u);
        EXPECT_EQ(both.device, both.cpu)
            << "stretched by (" << stretch.x << ", " << stretch.y << ", " << stretch.z
            << "): " << both.device.size() << " pairs on the device, " << both.cpu.size()
            << " on the CPU";
    }
}

// Every small body at one point: their boxes all overlap, so that each entry's sweep runs to the
// end of its column, and every pair of them is found, as on the CPU.
TEST_F(SatTwin, BroadPhaseMatchesTheCpuWithEveryBoxInOnePlace) {
    test::StageInput in = broadPhaseScene(21, 60, false);
    for (std::uint32_t i = 2; i + 2 < in.bodies.count(); ++i)
        in.bodies.poses[i].position = shared::vec4(1.0f, 2.0f, 3.0f);
    std::unique_ptr<test::DeviceStage> device = satStageOf(in);
    SatCollision cpu(ContactForm::Manifolds);
    const BothPairs both = findBoth(*device, cpu, in);
    ASSERT_GE(both.cpu.size(), std::size_t(60 * 59 / 2));
    EXPECT_EQ(both.device, both.cpu);
}

// More pairs than the buffers hold at first (four per body): they grow and the pairs are found
// again, all of them.
TEST_F(SatTwin, APairOverflowGrowsTheBuffers) {
    test::StageInput in = broadPhaseScene(9, 300, false);
    // Everything in one heap: most boxes overlap most others.
    for (std::uint32_t i = 2; i + 2 < in.bodies.count(); ++i)
        in.bodies.poses[i].position = shared::scale4(in.bodies.poses[i].position, 0.15f);
    std::unique_ptr<test::DeviceStage> device = satStageOf(in);
    const std::uint32_t capacity = device->pairs.current.capacity;
    SatCollision cpu(ContactForm::Manifolds);
    const BothPairs both = findBoth(*device, cpu, in);
    ASSERT_GT(both.cpu.size(), capacity);
    EXPECT_GT(device->pairs.current.capacity, capacity);
    EXPECT_EQ(both.device, both.cpu);
}

// stack_10 settling on the CPU: every step, its state on both twins; the manifolds agree, the
// cached features agree, and once the stack rests every pair keeps its feature ids.
TEST_F(SatTwin, ARestingStackKeepsItsFeatureIdsOnBoth) {
    const std::string path = std::string(RUBBLE_SOURCE_DIR) + "/scenes/stack_10.json";
    Result<Scene> scene = loadScene(path);
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    Result<World> world = World::create(*scene);
    ASSERT_TRUE(world.ok());
    test::StageInput in = test::stageInput(*scene);
    std::unique_ptr<test::DeviceStage> device = satStageOf(in);
    test::DeviceStage& p = *device;
    SatCollision cpu(ContactForm::Manifolds);
    const StepParams params = in.params();
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> lastIds;
    int restingSteps = 0, keptIds = 0, changedIds = 0;
    for (int step = 0; step < 180; ++step) {
        ASSERT_TRUE(world->step().ok());
        test::takeState(*world, in);
        // Awake on both, so that every pair is tested.
        for (shared::BodyMass& m : in.bodies.masses) m.flags &= ~RUBBLE_BODY_ASLEEP;
        ASSERT_TRUE(p.uploadBodies(in.bodies.view()).ok());
        ASSERT_TRUE(p.resetStatus().ok());
        ASSERT_TRUE(p.broadPhase(params.dt).ok());
        ASSERT_TRUE(p.narrowPhase(params.dt).ok());
        Result<std::vector<BodyPair>> pairs = p.downloadPairs();
        Result<std::vector<shared::ContactManifold>> manifolds = p.downloadManifolds();
        Result<std::vector<shared::PairCache>> features = p.downloadPairFeatures();
        ASSERT_TRUE(pairs.ok() && manifolds.ok() && features.ok());
        StepContacts out;
        ASSERT_TRUE(cpu.broadPhase(in.collisionScene(), in.bodies.view(), params, out).ok());
        ASSERT_TRUE(cpu.narrowPhase(in.collisionScene(), in.bodies.view(), params, out).ok());
        ASSERT_EQ(*pairs, out.pairs) << "step " << step;
        ASSERT_EQ(out.manifolds.size(), 10u) << "step " << step; // floor and nine crates
        std::size_t k = 0;
        for (std::size_t i = 0; i < pairs->size(); ++i) {
            const shared::ContactManifold& d = (*manifolds)[i];
            const Manifold* m =
                k < out.manifolds.size() && out.manifolds[k].a == d.a && out.manifolds[k].b == d.b
                    ? &out.manifolds[k++]
                    : nullptr;
            EXPECT_EQ(difference(m, d), "") << "step " << step << ", pair " << d.a << "-" << d.b;
        }
        // The cached features of the hull pairs, as the CPU keeps them.
        const std::vector<CachedFeature>& cached = cpu.cache().features;
        std::size_t hullPairs = 0;
        for (std::size_t i = 0; i < pairs->size(); ++i) {
            const shared::PairCache& f = (*features)[i];
            if (!f.reusable) continue;
            ASSERT_LT(hullPairs, cached.size());
            const CachedFeature& c = cached[hullPairs++];
            EXPECT_EQ(c.pair, (*pairs)[i]);
            EXPECT_EQ(std::uint32_t(c.cache.feature.feature), f.feature.feature);
            EXPECT_EQ(c.cache.feature.indexA, f.feature.indexA);
            EXPECT_EQ(c.cache.feature.indexB, f.feature.indexB);
            EXPECT_EQ(c.cache.reference.translation.y, f.reference.translation.y);
        }
        EXPECT_EQ(hullPairs, cached.size());
        // Resting from step 90 on (the top crate still rocks a little at steps 60 to 64, which
        // changes two of its clip ids on both): each pair's ids are last step's.
        if (step >= 90) {
            ++restingSteps;
            for (const shared::ContactManifold& d : *manifolds) {
                std::vector<std::uint32_t> ids(d.features, d.features + d.count);
                std::sort(ids.begin(), ids.end());
                std::vector<std::uint32_t>& last = lastIds[{d.a, d.b}];
                (ids == last ? keptIds : changedIds) += 1;

                last = ids;
            }
        } else {
            for (const shared::ContactManifold& d : *manifolds) {
                std::vector<std::uint32_t> ids(d.features, d.features + d.count);
                std::sort(ids.begin(), ids.end());
                lastIds[{d.a, d.b}] = ids;
            }
        }
        ASSERT_TRUE(p.keepPairFeatures().ok());
    }
    EXPECT_EQ(restingSteps, 90);
    EXPECT_EQ(changedIds, 0);
    EXPECT_EQ(keptIds, 90 * 10);
}

} // namespace
} // namespace rubble
