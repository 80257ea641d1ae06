// tests/unit/contact_recycling_test.cpp: contact recycling (rubble/shared/contact_recycling.h) in
// the CPU narrow phase: a recycled manifold against a fresh one, and the limits that refresh it.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "host/collision/sat_collision.h"
#include "host/core/math.h"
#include "rubble/world.h"
#include "support/stage_input.h"

namespace rubble {
namespace {

// A static table (half extents 0.5) and a crate (half extents 0.3) on it, its centre at (x, y),
// by default resting 1 mm deep; recycling as asked.
std::string tableScene(bool recycle, float x, float y = 0.799f) {
    return R"({"format": "rubble-scene", "version": 1, "name": "t",
      "simulation": {"collision": {"recycle_contacts": )" +
           std::string(recycle ? "true" : "false") + R"(}},
      "shapes": {"table": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "crate": {"type": "box", "half_extents": [0.3, 0.3, 0.3]}},
      "bodies": [{"name": "table", "shape": "table", "static": true, "position": [0, 0, 0]},
                 {"name": "crate", "shape": "crate", "mass": 1, "position": [)" +
           std::to_string(x) + ", " + std::to_string(y) + R"(, 0.05]}]})";
}

// The SAT stages on a scene's bodies, with their contacts.
struct Sat {
    explicit Sat(const std::string& text) : in(test::stageInput(text)) {}
    void step() {
        Status st = stage.broadPhase(in.collisionScene(), in.bodies.view(), in.params(), c);
        ASSERT_TRUE(st.ok()) << st.error().describe();
        st = stage.narrowPhase(in.collisionScene(), in.bodies.view(), in.params(), c);
        ASSERT_TRUE(st.ok()) << st.error().describe();
    }
    // Moves the crate (body 1) by d and turns it by `angle` about `axis` from its start.
    void place(glm::vec3 d, float angle, glm::vec3 axis) {
        in.bodies.poses[1].position = add(start, d);
        in.bodies.poses[1].orientation = toFloat4(glm::angleAxis(angle, glm::normalize(axis)));
    }
    static shared::float4 add(shared::float4 a, glm::vec3 d) {
        return shared::make4(a.x + d.x, a.y + d.y, a.z + d.z, a.w);
    }
    const Manifold& only() const {
        EXPECT_EQ(c.manifolds.size(), 1u);
        return c.manifolds.at(0);
    }
    std::uint32_t age() const { return stage.cache().recycled.at(0).age; }
    test::StageInput in;
    SatCollision stage{ContactForm::Manifolds};
    StepContacts c;
    shared::float4 start = in.bodies.poses[1].position;
};

// The point of `m` with feature id `id`, or nullptr.
const ContactPoint* pointWithId(const Manifold& m, std::uint32_t id) {
    for (std::uint32_t i = 0; i < m.count; ++i)
        if (m.points[i].feature == id) return &m.points[i];
    return nullptr;
}

std::vector<std::uint32_t> featureIds(const Manifold& m) {
    std::vector<std::uint32_t> ids;
    for (std::uint32_t i = 0; i < m.count; ++i) ids.push_back(m.points[i].feature);
    std::sort(ids.begin(), ids.end());
    return ids;
}

TEST(ContactRecycling, SmallMotionGivesTheFreshManifold) {
    Sat recycling(tableScene(true, 0.1f));
    recycling.step();
    ASSERT_EQ(recycling.only().count, 4u);
    EXPECT_EQ(recycling.age(), 0u);
    // Within the 0.25 mm limit: 0.12 mm down and sideways, turned 0.2 mrad (0.1 mm at the
    // crate's corners).
    const glm::vec3 d(0.00005f, -0.0001f, 0.00003f);
    const float angle = 0.0002f;
    const glm::vec3 axis(0.3f, 0.2f, 1.0f);
    recycling.place(d, angle, axis);
    recycling.step();
    EXPECT_EQ(recycling.age(), 1u) << "the manifold was recycled";
    // The same pose through a stage that has never seen the pair: SAT and clipping.
    Sat fresh(tableScene(false, 0.1f));
    fresh.place(d, angle, axis);
    fresh.step();
    const Manifold& r = recycling.only();
    const Manifold& f = fresh.only();
    ASSERT_EQ(featureIds(r), featureIds(f));
    EXPECT_NEAR(glm::length(r.normal - f.normal), 0.0f, 1e-6f);
    for (std::uint32_t i = 0; i < f.count; ++i) {
        const ContactPoint* p = pointWithId(r, f.points[i].feature);
        ASSERT_NE(p, nullptr);
        EXPECT_NEAR(p->depth, f.points[i].depth, 1e-6f) << "point " << i;
        EXPECT_NEAR(glm::length(p->position - f.points[i].position), 0.0f, 2e-6f) << "point " << i;
        EXPECT_NEAR(glm::length(p->normal - f.points[i].normal), 0.0f, 1e-6f);
    }
    // The depths moved with the crate: 1 mm deep at the start, 1.1 mm give or take the tilt.
    for (std::uint32_t i = 0; i < r.count; ++i) {
        EXPECT_GT(r.points[i].depth, 0.001f);
        EXPECT_LT(r.points[i].depth, 0.0012f);
    }
}

TEST(ContactRecycling, MotionBeyondTheLimitIsRecomputed) {
    // The crate's +x corners 0.2 mm inside the table's edge.
    Sat recycling(tableScene(true, 0.1998f)), plain(tableScene(false, 0.1998f));
    recycling.step();
    plain.step();
    const std::vector<std::uint32_t> before = featureIds(recycling.only());
    ASSERT_EQ(before, featureIds(plain.only()));
    // 3 mm along x (past the 0.25 mm limit): two corners leave the table, whose edge clips instead.
    for (Sat* s : {&recycling, &plain}) {
        s->place(glm::vec3(0.003f, 0.0f, 0.0f), 0.0f, glm::vec3(0, 1, 0));
        s->step();
    }
    EXPECT_EQ(recycling.age(), 0u) << "the manifold was made again";
    EXPECT_NE(featureIds(recycling.only()), before);
    EXPECT_EQ(std::memcmp(&recycling.only(), &plain.only(), sizeof(Manifold)), 0);
    // A turn alone past the limit: 0.01 rad turns the crate's corners by 4 mm.
    for (Sat* s : {&recycling, &plain}) {
        s->place(glm::vec3(0.003f, 0.0f, 0.0f), 0.01f, glm::vec3(0, 1, 0));
        s->step();
    }
    EXPECT_EQ(recycling.age(), 0u);
    EXPECT_EQ(std::memcmp(&recycling.only(), &plain.only(), sizeof(Manifold)), 0);
}

TEST(ContactRecycling, ARestingPairIsRefreshedEveryFewSteps) {
    Sat recycling(tableScene(true, 0.1f));
    std::vector<std::uint32_t> ages;
    for (std::uint32_t k = 0; k < 2 * RUBBLE_RECYCLE_MAX_AGE + 2; ++k) {
        recycling.step();
        ages.push_back(recycling.age());
    }
    // 0 (made), 1 .. max age (recycled), 0 (made again), ...
    for (std::uint32_t k = 0; k < ages.size(); ++k)
        EXPECT_EQ(ages[k], k % (RUBBLE_RECYCLE_MAX_AGE + 1)) << "step " << k;
}

TEST(ContactRecycling, PointsBeyondTheMarginAreLeftOut) {
    // The crate 3.8 mm above the table: four speculative points, 0.2 mm inside the 4 mm margin.
    Sat recycling(tableScene(true, 0.1f, 0.8038f));
    recycling.step();
    ASSERT_EQ(recycling.only().count, 4u);
    // 0.1 mm up: recycled, each point's gap 3.9 mm.
    recycling.place(glm::vec3(0.0f, 0.0001f, 0.0f), 0.0f, glm::vec3(0, 1, 0));
    recycling.step();
    EXPECT_EQ(recycling.age(), 1u);
    ASSERT_EQ(recycling.only().count, 4u);
    for (std::uint32_t i = 0; i < 4; ++i)
        EXPECT_NEAR(recycling.only().points[i].depth, -0.0039f, 1e-6f);
    // 0.24 mm up, within the limit but 4.04 mm apart: no point is left, the full test finds none.
    recycling.place(glm::vec3(0.0f, 0.00024f, 0.0f), 0.0f, glm::vec3(0, 1, 0));
    recycling.step();
    EXPECT_TRUE(recycling.c.manifolds.empty());
}

TEST(ContactRecycling, ASeparatedPairStaysSeparatedWhileItMovesLessThanItsGap) {
    // The crate turned 45 degrees about y beside the table's vertical edge at (0.5, 0.5): its
    // face 0.22 sqrt 2 - 0.3 = 11.1 mm from the edge, its box overlapping the table's.
    const float d = 0.22f;
    const float gap = d * std::sqrt(2.0f) - 0.3f;
    Sat recycling(R"({"format": "rubble-scene", "version": 1, "name": "t",
      "simulation": {"collision": {"recycle_contacts": true}},
      "shapes": {"table": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "crate": {"type": "box", "half_extents": [0.3, 0.3, 0.3]}},
      "bodies": [{"name": "table", "shape": "table", "static": true, "position": [0, 0, 0]},
                 {"name": "crate", "shape": "crate", "mass": 1, "position": [0.72, 0, 0.72],
                  "orientation": [0.9238795, 0, 0.3826834, 0]}]})");
    recycling.step();
    ASSERT_EQ(recycling.c.pairs.size(), 1u);
    EXPECT_TRUE(recycling.c.manifolds.empty());
    EXPECT_NEAR(recycling.stage.cache().recycled.at(0).gap, gap, 1e-5f);
    const float made = recycling.stage.cache().recycled.at(0).made.translation.x;
    const glm::vec3 towards = glm::normalize(glm::vec3(-1.0f, 0.0f, -1.0f));
    const float angle = glm::radians(45.0f);
    // 5 mm closer: 6.1 mm apart, more than the margin; the pair is not tested again.
    recycling.place(0.005f * towards, angle, glm::vec3(0, 1, 0));
    recycling.step();
    EXPECT_TRUE(recycling.c.manifolds.empty());
    EXPECT_EQ(recycling.stage.cache().recycled.at(0).made.translation.x, made);
    // 8 mm closer, 3.1 mm apart: tested again, speculative points at that gap.
    recycling.place(0.008f * towards, angle, glm::vec3(0, 1, 0));
    recycling.step();
    ASSERT_GE(recycling.only().count, 1u);
    for (std::uint32_t i = 0; i < recycling.only().count; ++i)
        EXPECT_NEAR(recycling.only().points[i].depth, -(gap - 0.008f), 2e-5f);
}

// The device's SAT collides every pair every step: asking it to recycle is refused, naming the
// option.
TEST(ContactRecycling, OnlyTheCpuSatPathTakesIt) {
    for (const char* simulation :
         {R"("backend": "opencl", "collision": {"method": "sat", "recycle_contacts": true})",
          R"("collision": {"method": "particles", "recycle_contacts": true})"}) {
        const std::string text = R"({"format": "rubble-scene", "version": 1, "name": "t",
          "simulation": {)" + std::string(simulation) +
                                 R"(},
          "shapes": {"crate": {"type": "box", "half_extents": [0.3, 0.3, 0.3]}},
          "bodies": [{"name": "crate", "shape": "crate", "mass": 1}]})";
        Result<Scene> scene = parseScene(text, "inline.json", ".");
        ASSERT_TRUE(scene.ok()) << scene.error().describe();
        Result<World> world = World::create(*scene);
        ASSERT_FALSE(world.ok()) << simulation;
        EXPECT_EQ(world.error().kind, ErrorKind::NotSupported);
        EXPECT_EQ(world.error().where, "inline.json: simulation.collision.recycle_contacts");
    }
}

} // namespace
} // namespace rubble
