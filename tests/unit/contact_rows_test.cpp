// tests/unit/contact_rows_test.cpp: host/dynamics/contact_rows with hand-made manifolds: row
// masses, targets, material mixing, tangents, filters, warm starting and row order.
#include "host/dynamics/contact_rows.h"

#include <cmath>

#include <gtest/gtest.h>

#include "host/core/math.h"

namespace rubble {
namespace {

using shared::BodyMass;
using shared::BodyPose;
using shared::BodyVelocity;

// Body 0: static ground. Body 1: a 2 kg cube of side 1 (I = m/6 = 1/3 kg m^2) at (0, 0.5, 0).
// Body 2: another such cube at (3, 0.5, 0).
struct Fixture {
    std::vector<BodyMass> masses;
    std::vector<BodyPose> poses;
    std::vector<BodyVelocity> velocities;
    std::vector<BodyVelocity> beforeForces; ///< the same as velocities unless a test sets them
    std::vector<MaterialDesc> materials{{"default", 0.5f, 0.0f}};
    std::vector<std::uint32_t> materialOf{0, 0, 0};
    SolverBodies bodies;
    ContactRowSettings settings;

    Fixture() {
        BodyMass ground{};
        ground.flags = RUBBLE_BODY_STATIC;
        BodyMass cube{};
        cube.mass = 2.0f;
        cube.inverseMass = 0.5f;
        cube.inertiaBody = toShared(glm::mat3(1.0f / 3.0f));
        cube.inverseInertiaBody = toShared(glm::mat3(3.0f));
        masses = {ground, cube, cube};
        const float4 identity = shared::make4(0, 0, 0, 1);
        poses = {{shared::vec4(0, 0, 0), identity},
                 {shared::vec4(0, 0.5f, 0), identity},
                 {shared::vec4(3, 0.5f, 0), identity}};
        velocities.assign(3, BodyVelocity{});
        beforeForces.assign(3, BodyVelocity{});
    }
    void setVelocity(std::uint32_t i, glm::vec3 v) {
        velocities[i].linear = toFloat4(v);
        beforeForces[i].linear = toFloat4(v);
    }
    ContactRows build(const std::vector<Manifold>& manifolds, std::span<const BodyPair> joined = {},
                      std::span<const ContactImpulse> last = {}) {
        gatherSolverMasses(masses, poses, bodies);
        gatherSolverVelocities(velocities, bodies);
        ContactRows rows;
        buildContactRows(manifolds, poses, bodies, beforeForces, materials, materialOf, joined,
                         last, settings, rows);
        return rows;
    }
};

// The ground under body `b`: normal up, points at the corners of its bottom face.
Manifold floorContact(std::uint32_t b, float x, float depth, std::uint32_t count = 4) {
    Manifold m;
    m.a = 0;
    m.b = b;
    m.normal = {0, 1, 0};
    m.count = count;
    const glm::vec2 corners[4] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};
    for (std::uint32_t k = 0; k < count; ++k)
        m.points[k] =
            ContactPoint{{x + corners[k].x, -depth / 2, corners[k].y}, depth, 10 + k, m.normal};
    return m;
}

TEST(ContactRows, RowMassIsTheInverseOfJMinvJt) {
    Fixture f;
    const ContactRows rows = f.build({floorContact(1, 0.0f, 0.001f, 1)});
    ASSERT_EQ(rows.size(), 1u);
    // r_b = (-0.5, -0.5, -0.5): r x n = (0.5, 0, -0.5); k = 1/m + 3 * 0.5 = 2.
    EXPECT_NEAR(rows.normals[0].mass, 0.5f, 1e-6f);
    EXPECT_EQ(rows.normals[0].inverseMassA, 0.0f);
    EXPECT_EQ(rows.normals[0].inverseMassB, 0.5f);
    const glm::vec3 crossB = fromLanes(rows.normals[0].crossB);
    EXPECT_NEAR(glm::length(crossB - glm::vec3(0.5f, 0.0f, -0.5f)), 0.0f, 1e-6f);
}

TEST(ContactRows, TargetsStopOrCloseTheGapAndBouncesLeaveAtETimesTheContactSpeed) {
    Fixture f;
    f.materials[0].restitution = 0.5f;
    // Touching at 2 m/s: the solve stops it, the bounce leaves at e 2 m/s.
    f.setVelocity(1, {0, -2, 0});
    ContactRows rows = f.build({floorContact(1, 0, 0.001f)});
    EXPECT_EQ(rows.normals[0].targetSpeed, 0.0f);
    EXPECT_NEAR(rows.normals[0].bounceSpeed, 1.0f, 1e-5f);
    // Below the restitution threshold a contact only stops.
    f.setVelocity(1, {0, -0.3f, 0});
    EXPECT_EQ(f.build({floorContact(1, 0, 0.001f)}).normals[0].bounceSpeed, 0.0f);
    // A 1 cm gap that 0.3 m/s does not close in 1/60 s: approach up to 0.6 m/s is allowed.
    EXPECT_NEAR(f.build({floorContact(1, 0, -0.01f)}).normals[0].targetSpeed, -0.6f, 1e-5f);
    // A gap of 2 cm closed at 2 m/s before this step's gravity and 2 + g dt after it: the gap
    // closes exactly in the solve, and the bounce leaves from the contact at e 2 m/s, the speed
    // it arrived with. On the path the symplectic steps sample (2 + g dt / 2 m/s at the step's
    // start) the box meets the floor at u_c = sqrt(u0^2 + 2 g gap) and rises to (e u_c)^2 / 2g;
    // the split pass lifts it to where the later steps at e 2 - k g dt m/s reach that apex.
    const double g = 9.81, dt = 1.0 / 60.0, gap = 0.02, e = 0.5;
    f.setVelocity(1, {0, float(-2.0 - g * dt), 0});
    f.beforeForces[1].linear = toFloat4(glm::vec3(0, -2, 0));
    rows = f.build({floorContact(1, 0, -float(gap))});
    const double u0 = 2.0 + 0.5 * g * dt, uc = std::sqrt(u0 * u0 + 2.0 * g * gap);
    const double leave = e * 2.0;
    double later = 0.0;
    for (double v = leave - g * dt; v > 0.0; v -= g * dt) later += v * dt;
    EXPECT_NEAR(rows.normals[0].targetSpeed, -gap / dt, 1e-4);
    EXPECT_NEAR(rows.normals[0].bounceSpeed, leave, 1e-6);
    EXPECT_NEAR(rows.normals[0].bounceLift, ((e * uc) * (e * uc) / (2.0 * g) - later) / dt, 1e-3);
    // At rest before the forces, whatever gravity adds within the step: no bounce (at 10 Hz
    // gravity alone adds 0.98 m/s, above the threshold).
    f.setVelocity(1, {0, -0.981f, 0});
    f.beforeForces[1].linear = toFloat4(glm::vec3(0.0f));
    EXPECT_EQ(f.build({floorContact(1, 0, 0.001f)}).normals[0].bounceSpeed, 0.0f);
}

TEST(ContactRows, BaumgarteSpeedGoesToThePositionPassAboveTheSlop) {
    Fixture f;
    EXPECT_EQ(f.build({floorContact(1, 0, 0.004f)}).normals[0].pushSpeed, 0.0f);
    // beta / dt (depth - slop) = 0.2 * 60 * 0.015
    EXPECT_NEAR(f.build({floorContact(1, 0, 0.02f)}).normals[0].pushSpeed, 0.18f, 1e-5f);
    EXPECT_EQ(f.build({floorContact(1, 0, 0.5f)}).normals[0].pushSpeed, kMaxPushSpeed);
    EXPECT_EQ(f.build({floorContact(1, 0, 0.5f)}).normals[0].targetSpeed, 0.0f);
}

TEST(ContactRows, MaterialsCombineAsSqrtAndMax) {
    Fixture f;
    f.materials = {{"default", 0.5f, 0.0f}, {"ice", 0.25f, 0.0f}, {"rough", 1.0f, 0.7f}};
    f.materialOf = {1, 2, 0};
    f.setVelocity(1, {0, -3, 0});
    const ContactRows rows = f.build({floorContact(1, 0, 0.001f, 1)});
    EXPECT_NEAR(rows.frictions[0].friction, 0.5f, 1e-6f);
    EXPECT_NEAR(rows.normals[0].bounceSpeed, 0.7f * 3.0f, 1e-5f);
}

TEST(ContactRows, TangentsFollowTheSlidingDirection) {
    Fixture f;
    f.setVelocity(1, {3, 0, 4});
    const FrictionRows fr = f.build({floorContact(1, 0, 0.001f, 1)}).frictions[0];
    EXPECT_NEAR(glm::length(fromLanes(fr.tangent[0]) - glm::vec3(0.6f, 0, 0.8f)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(fromLanes(fr.tangent[1]), glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(fromLanes(fr.tangent[0]), fromLanes(fr.tangent[1])), 0.0f, 1e-6f);
    glm::vec3 t1, t2;
    for (const glm::vec3 n :
         {glm::vec3(0, 1, 0), glm::normalize(glm::vec3(1, 1, 1)), glm::vec3(-1, 0, 0)}) {
        tangentBasis(n, t1, t2);
        EXPECT_NEAR(glm::length(t1), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(glm::cross(t1, t2), n), 1.0f, 1e-6f); // right-handed
    }
}

TEST(ContactRows, JoinedAndMotionlessPairsMakeNoRows) {
    Fixture f;
    const BodyPair joined[] = {{0, 1}};
    EXPECT_EQ(f.build({floorContact(1, 0, 0.001f)}, joined).size(), 0u);
    EXPECT_TRUE(isJoinedPair(joined, 1, 0));
    EXPECT_FALSE(isJoinedPair(joined, 0, 2));
    f.masses[1].flags |= RUBBLE_BODY_ASLEEP;
    EXPECT_EQ(f.build({floorContact(1, 0, 0.001f)}).size(), 0u);
}

TEST(ContactRows, WarmStartMatchesFeaturesThenNearestPoints) {
    Fixture f;
    f.setVelocity(1, {1, 0, 0});
    ContactRows rows = f.build({floorContact(1, 0, 0.001f)});
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows.normals[i].impulse = 1.0f + float(i);
        rows.frictions[i].impulse[0] = -0.1f;
    }
    std::vector<ContactImpulse> last, scratch;
    storeContactImpulses(rows, {}, f.bodies, last, scratch);
    ASSERT_EQ(last.size(), 4u);
    // Same features: the same impulses, friction kept along the same tangent.
    const ContactRows same = f.build({floorContact(1, 0, 0.001f)}, {}, last);
    for (std::size_t i = 0; i < same.size(); ++i) {
        EXPECT_EQ(same.normals[i].impulse, rows.normals[i].impulse);
        EXPECT_NEAR(same.frictions[i].impulse[0], -0.1f, 1e-6f);
    }
    // New feature ids at the same places: matched by position.
    Manifold renamed = floorContact(1, 0, 0.001f);
    for (std::uint32_t k = 0; k < 4; ++k) renamed.points[k].feature = 90 + k;
    const ContactRows near = f.build({renamed}, {}, last);
    for (std::size_t i = 0; i < near.size(); ++i)
        EXPECT_EQ(near.normals[i].impulse, rows.normals[i].impulse);
    // New features 10 cm away: nothing to take over.
    Manifold moved = floorContact(1, 0.1f, 0.001f);
    for (std::uint32_t k = 0; k < 4; ++k) moved.points[k].feature = 90 + k;
    for (const NormalRow& r : f.build({moved}, {}, last).normals) EXPECT_EQ(r.impulse, 0.0f);
    // Warm starting off: nothing either.
    f.settings.warmStart = false;
    for (const NormalRow& r : f.build({floorContact(1, 0, 0.001f)}, {}, last).normals)
        EXPECT_EQ(r.impulse, 0.0f);
}

TEST(ContactRows, WarmStartFindsEachPairsImpulsesInAnyManifoldOrder) {
    Fixture f;
    ContactRows rows = f.build({floorContact(1, 0, 0.001f), floorContact(2, 3, 0.001f)});
    for (NormalRow& r : rows.normals) r.impulse = r.b == 1 ? 1.0f : 2.0f;
    std::vector<ContactImpulse> last, scratch;
    storeContactImpulses(rows, {}, f.bodies, last, scratch);
    ASSERT_EQ(last.size(), 8u);
    // The pairs in reverse order: the second manifold's run lies before the first's.
    for (const NormalRow& r :
         f.build({floorContact(2, 3, 0.001f), floorContact(1, 0, 0.001f)}, {}, last).normals)
        EXPECT_EQ(r.impulse, r.b == 1 ? 1.0f : 2.0f);
    // A pair with no old impulses between and after two that have them.
    f.masses.push_back(f.masses[1]);
    f.poses.push_back(f.poses[1]);
    f.velocities.push_back({});
    f.beforeForces.push_back({});
    f.materialOf.push_back(0);
    Manifold lifted = floorContact(3, 6, 0.001f);
    lifted.a = 2;
    const ContactRows mixed =
        f.build({floorContact(1, 0, 0.001f), lifted, floorContact(2, 3, 0.001f)}, {}, last);
    ASSERT_EQ(mixed.size(), 12u);
    for (const NormalRow& r : mixed.normals)
        EXPECT_EQ(r.impulse, r.a == 2 ? 0.0f : r.b == 1 ? 1.0f : 2.0f);
}

TEST(ContactRows, RowsInterleavePointsAndStoreInManifoldOrder) {
    Fixture f;
    ContactRows rows = f.build({floorContact(1, 0, 0.001f, 2), floorContact(2, 3, 0.001f, 3)});
    ASSERT_EQ(rows.size(), 5u);
    // Point-major: (1, p0), (2, p0), (1, p1), (2, p1), (2, p2).
    const std::uint32_t bodies[] = {1, 2, 1, 2, 2}, features[] = {10, 10, 11, 11, 12};
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_EQ(rows.normals[i].b, bodies[i]);
        EXPECT_EQ(rows.keys[i].feature, features[i]);
        rows.normals[i].impulse = float(i);
    }
    std::vector<ContactImpulse> last, scratch;
    storeContactImpulses(rows, {}, f.bodies, last, scratch);
    const float inOrder[] = {0, 2, 1, 3, 4};
    for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(last[i].normal, inOrder[i]);
}

TEST(ContactRows, SleepingPairsKeepTheirImpulsesUntilWoken) {
    Fixture f;
    ContactRows rows = f.build({floorContact(1, 0, 0.001f), floorContact(2, 3, 0.001f)});
    for (NormalRow& r : rows.normals) r.impulse = r.b == 1 ? 1.0f : 2.0f;
    std::vector<ContactImpulse> first, second, scratch;
    storeContactImpulses(rows, {}, f.bodies, first, scratch);
    // Body 1 falls asleep: its contact makes no row, but its impulses are kept, in pair order.
    f.masses[1].flags |= RUBBLE_BODY_ASLEEP;
    const ContactRows asleep =
        f.build({floorContact(1, 0, 0.001f), floorContact(2, 3, 0.001f)}, {}, first);
    ASSERT_EQ(asleep.size(), 4u);
    storeContactImpulses(asleep, first, f.bodies, second, scratch);
    ASSERT_EQ(second.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(second[i].b, i < 4 ? 1u : 2u);
    // Woken, it starts from them.
    f.masses[1].flags &= ~RUBBLE_BODY_ASLEEP;
    for (const NormalRow& r : f.build({floorContact(1, 0, 0.001f)}, {}, second).normals)
        EXPECT_EQ(r.impulse, 1.0f);
}

} // namespace
} // namespace rubble
