// tests/unit/pgs_test.cpp: host/dynamics/pgs on hand-made contacts: non-penetration, impulse
// totals, the friction box, warm starting, relaxation and the split position pass.
#include "host/dynamics/pgs.h"

#include <cmath>

#include <gtest/gtest.h>

#include "host/core/math.h"

namespace rubble {
namespace {

// A 2 kg unit cube (I = 1/3 kg m^2) at (0, 0.5, 0) on a static ground, four corner contacts.
struct Landing {
    std::vector<shared::BodyMass> masses;
    std::vector<shared::BodyPose> poses;
    std::vector<shared::BodyVelocity> velocities;
    std::vector<MaterialDesc> materials{{"default", 0.5f, 0.0f}};
    std::vector<std::uint32_t> materialOf{0, 0};
    SolverBodies bodies;
    ContactRows rows;
    SolverOptions options;

    explicit Landing(glm::vec3 velocity, float depth = 0.001f, float restitution = 0.0f) {
        materials[0].restitution = restitution;
        shared::BodyMass ground{}, cube{};
        ground.flags = RUBBLE_BODY_STATIC;
        cube.mass = 2.0f;
        cube.inverseMass = 0.5f;
        cube.inertiaBody = toShared(glm::mat3(1.0f / 3.0f));
        cube.inverseInertiaBody = toShared(glm::mat3(3.0f));
        masses = {ground, cube};
        const float4 identity = shared::make4(0, 0, 0, 1);
        poses = {{shared::vec4(0, 0, 0), identity}, {shared::vec4(0, 0.5f, 0), identity}};
        velocities.assign(2, shared::BodyVelocity{});
        velocities[1].linear = toFloat4(velocity);
        Manifold m;
        m.a = 0;
        m.b = 1;
        m.normal = {0, 1, 0};
        m.count = 4;
        const glm::vec2 c[4] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};
        for (std::uint32_t k = 0; k < 4; ++k)
            m.points[k] = ContactPoint{{c[k].x, 0.0f, c[k].y}, depth, k, m.normal};
        gatherSolverMasses(masses, poses, bodies);
        gatherSolverVelocities(velocities, bodies);
        buildContactRows(std::vector<Manifold>{m}, poses, bodies, velocities, materials, materialOf,
                         {}, {}, ContactRowSettings{}, rows);
    }
    glm::vec3 linear() const { return fromLanes(bodies.velocity[1].linear); }
    glm::vec3 angular() const { return fromLanes(bodies.velocity[1].angular); }
    float totalNormal() const {
        float sum = 0.0f;
        for (const NormalRow& r : rows.normals) sum += r.impulse;
        return sum;
    }
};

TEST(Pgs, LandingBoxStopsWithImpulsesThatAddUp) {
    Landing l({0, -1, 0});
    std::vector<float> residuals;
    l.options.iterations = 30;
    solvePgs(l.rows, {}, l.bodies, l.options, residuals);
    ASSERT_EQ(residuals.size(), 30u);
    EXPECT_NEAR(l.linear().y, 0.0f, 1e-4f);
    EXPECT_NEAR(glm::length(l.angular()), 0.0f, 1e-4f);
    // m dv = 2 kg * 1 m/s, shared by the corners, none pulling.
    EXPECT_NEAR(l.totalNormal(), 2.0f, 1e-4f);
    for (const NormalRow& r : l.rows.normals) EXPECT_GE(r.impulse, 0.0f);
    // It converges: the last sweep changes far less than the first.
    EXPECT_LT(residuals.back(), 1e-3f * residuals.front());
}

TEST(Pgs, RestitutionPassGivesTheStoppedApproachBackTimesE) {
    // Restitution 0.8 at 2 m/s: the solve stops the box, the pass sends it up at 1.6 m/s, flat
    // (the four corners share it), and the momenta take m 1.6 m/s.
    Landing l({0, -2, 0}, 0.001f, 0.8f);
    std::vector<float> residuals;
    l.options.iterations = 30;
    solvePgs(l.rows, {}, l.bodies, l.options, residuals);
    EXPECT_NEAR(l.linear().y, 0.0f, 1e-4f);
    ASSERT_TRUE(solveRestitution(l.rows, l.bodies, 30));
    EXPECT_NEAR(l.linear().y, 1.6f, 1e-4f);
    EXPECT_NEAR(glm::length(l.angular()), 0.0f, 1e-4f);
    std::vector<shared::BodyMomentum> momenta(2);
    addBounceImpulses(l.rows, momenta);
    EXPECT_NEAR(momenta[1].linear.y, 2.0f * 1.6f, 1e-4f);
    EXPECT_NEAR(glm::length(toVec3(momenta[1].angular)), 0.0f, 1e-4f);
    EXPECT_EQ(toVec3(momenta[0].linear), glm::vec3(0.0f)); // the static ground takes nothing
    // A contact that does not bounce leaves the pass with nothing to do.
    Landing slow({0, -0.3f, 0}, 0.001f, 0.8f);
    solvePgs(slow.rows, {}, slow.bodies, slow.options, residuals);
    EXPECT_FALSE(solveRestitution(slow.rows, slow.bodies, 30));
}

TEST(Pgs, SeparatingBoxGetsNoImpulse) {
    Landing l({0, 0.5f, 0});
    std::vector<float> residuals;
    solvePgs(l.rows, {}, l.bodies, l.options, residuals);
    EXPECT_EQ(l.totalNormal(), 0.0f);
    EXPECT_EQ(l.linear().y, 0.5f);
}

TEST(Pgs, SlidingBoxFrictionStaysInTheBox) {
    // Down at 1 m/s and sideways at 3 m/s: the normal impulse 2 N s allows 1 N s of friction.
    Landing l({3, -1, 0});
    std::vector<float> residuals;
    l.options.iterations = 30;
    solvePgs(l.rows, {}, l.bodies, l.options, residuals);
    float friction = 0.0f;
    for (std::size_t i = 0; i < l.rows.size(); ++i) {
        const FrictionRows& f = l.rows.frictions[i];
        EXPECT_LE(std::abs(f.impulse[0]), 0.5f * l.rows.normals[i].impulse + 1e-6f);
        EXPECT_LE(std::abs(f.impulse[1]), 0.5f * l.rows.normals[i].impulse + 1e-6f);
        friction += f.impulse[0];
    }
    EXPECT_NEAR(friction, -0.5f * l.totalNormal(), 1e-3f);
    EXPECT_NEAR(l.linear().x, 3.0f - 0.5f * 2.0f / 2.0f, 1e-3f);
}

TEST(Pgs, StuckBoxFrictionStopsTheSlide) {
    // Sideways at 0.2 m/s: the 1 N s of friction available stops it.
    Landing l({0.2f, -1, 0});
    std::vector<float> residuals;
    l.options.iterations = 30;
    solvePgs(l.rows, {}, l.bodies, l.options, residuals);
    EXPECT_NEAR(l.linear().x, 0.0f, 1e-3f);
}

TEST(Pgs, WarmStartedRowsStartFromTheirImpulses) {
    Landing cold({0, -1, 0}), warm({0, -1, 0});
    for (NormalRow& r : warm.rows.normals) r.impulse = 0.5f; // the converged answer
    std::vector<float> coldResiduals, warmResiduals;
    cold.options.iterations = warm.options.iterations = 3;
    solvePgs(cold.rows, {}, cold.bodies, cold.options, coldResiduals);
    solvePgs(warm.rows, {}, warm.bodies, warm.options, warmResiduals);
    EXPECT_LT(warmResiduals.back(), 0.01f * coldResiduals.back());
    EXPECT_NEAR(warm.linear().y, 0.0f, 1e-5f);
}

TEST(Pgs, RelaxationScalesEachUpdate) {
    Landing full({0, -1, 0}), half({0, -1, 0});
    half.options.relaxation = 0.5f;
    full.options.iterations = half.options.iterations = 1;
    std::vector<float> a, b;
    solvePgs(full.rows, {}, full.bodies, full.options, a);
    solvePgs(half.rows, {}, half.bodies, half.options, b);
    // The first row sees the same speed in both: half the impulse.
    EXPECT_NEAR(half.rows.normals[0].impulse, 0.5f * full.rows.normals[0].impulse, 1e-6f);
}

TEST(Pgs, PositionPassPushesOutWithoutVelocity) {
    Landing l({0, 0, 0}, 0.05f);
    std::vector<float> residuals;
    solvePgs(l.rows, {}, l.bodies, l.options, residuals);
    EXPECT_EQ(l.linear(), glm::vec3(0.0f)) << "the velocity solve leaves a resting box alone";
    ASSERT_TRUE(solvePushes(l.rows, l.bodies, 20, 1.0f));
    // beta / dt (depth - slop) = 0.2 * 60 * 0.045 = 0.54 m/s of pseudo-velocity.
    EXPECT_NEAR(fromLanes(l.bodies.push[1].linear).y, 0.54f, 1e-3f);
    EXPECT_EQ(l.linear(), glm::vec3(0.0f));
    Landing shallow({0, 0, 0}, 0.002f);
    EXPECT_FALSE(solvePushes(shallow.rows, shallow.bodies, 20, 1.0f));
}

TEST(Pgs, SweepOrderKeepsEachBodysRowsInOrderAndSplitsChains) {
    // Body 0 is static, 1 to 6 move; rows (a, b) in ContactRows' order. Bodies 1 to 5 make one
    // island (the static body joins nothing), body 6 another.
    const std::uint32_t pairs[6][2] = {{1, 2}, {1, 3}, {4, 5}, {2, 4}, {0, 6}, {0, 1}};
    ContactRows rows;
    for (const auto& p : pairs) {
        NormalRow n;
        n.a = p[0];
        n.b = p[1];
        rows.normals.push_back(n);
        rows.frictions.push_back(FrictionRows{});
        rows.keys.push_back(ContactKey{p[0], p[1], 0u});
    }
    SolverBodies bodies;
    bodies.velocity.assign(7, SolverVelocity{});
    bodies.inverseMass = {0.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};
    packContactRows(rows, bodies, false);
    // The first island's waves 1, 2, 1, 2, 3: rows (1, 3) and (4, 5) trade places, so that no
    // two neighbours share a moving body; the second island's row comes after them.
    EXPECT_EQ(rows.sweep.place, (std::vector<std::uint32_t>{0, 2, 1, 3, 5, 4}));
    EXPECT_EQ(rows.sweep.islandStart, (std::vector<std::uint32_t>{0, 5, 6}));
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(rows.sweep.order[rows.sweep.place[i]], i);
        EXPECT_EQ(laneIndex(rows.sweep.normals[rows.sweep.place[i]].turnB[3]), pairs[i][1]);
    }
}

} // namespace
} // namespace rubble
