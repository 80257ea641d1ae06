// tests/unit/joints_test.cpp: host/dynamics/joints and joint_positions: joints in body frames,
// the velocity blocks, the Newton projection and its groups.
#include "host/dynamics/joints.h"

#include <cmath>

#include <gtest/gtest.h>

#include "host/core/math.h"
#include "host/dynamics/joint_positions.h"
#include "support/joint_gap.h"

namespace rubble {
namespace {

// Free 1 kg unit cubes (no gravity involved) at the given places, the first turned 30 degrees
// about z; a static body last.
struct Bodies {
    std::vector<shared::BodyMass> masses;
    std::vector<shared::BodyPose> poses;
    SolverBodies solver;

    explicit Bodies(std::vector<glm::vec3> centres) {
        shared::BodyMass cube{};
        cube.mass = 1.0f;
        cube.inverseMass = 1.0f;
        cube.inertiaBody = toShared(glm::mat3(1.0f / 6.0f));
        cube.inverseInertiaBody = toShared(glm::mat3(6.0f));
        for (std::size_t i = 0; i < centres.size(); ++i) {
            masses.push_back(cube);
            const glm::quat q = glm::angleAxis(i == 0 ? 0.5235988f : 0.0f, glm::vec3(0, 0, 1));
            poses.push_back({toFloat4(centres[i]), toFloat4(q)});
        }
        shared::BodyMass wall{};
        wall.flags = RUBBLE_BODY_STATIC;
        masses.push_back(wall);
        poses.push_back({shared::vec4(0, 0, 0), shared::make4(0, 0, 0, 1)});
        gatherSolverMasses(masses, poses, solver);
        solver.velocity.assign(masses.size(), SolverVelocity{});
    }
    glm::vec3 point(std::uint32_t body, glm::vec3 local) const {
        return toVec3(poses[body].position) +
               toVec3(shared::quatRotate(poses[body].orientation, toFloat4(local)));
    }
    /// Where a body's point `local` is after a step of h at the solver's velocities, moved as
    /// the integrator moves it (x += v h, turned by exp(w h)).
    glm::vec3 pointAfter(std::uint32_t body, glm::vec3 local, float h) const {
        const glm::vec3 w = fromLanes(solver.velocity[body].angular);
        const glm::quat turn =
            glm::length(w) > 0.0f ? glm::angleAxis(glm::length(w) * h, glm::normalize(w))
                                  : glm::quat(1, 0, 0, 0);
        const glm::vec3 r = toVec3(shared::quatRotate(poses[body].orientation, toFloat4(local)));
        return toVec3(poses[body].position) + fromLanes(solver.velocity[body].linear) * h +
               turn * r;
    }
    glm::vec3 pointVelocity(std::uint32_t body, glm::vec3 world) const {
        const glm::vec3 r = world - toVec3(poses[body].position);
        return fromLanes(solver.velocity[body].linear) +
               glm::cross(fromLanes(solver.velocity[body].angular), r);
    }
};

JointDesc joint(JointType type, std::uint32_t a, std::uint32_t b, glm::vec3 anchor,
                glm::vec3 axis = {0, 0, 1}) {
    JointDesc d;
    d.type = type;
    d.a = a;
    d.b = b;
    d.anchor = anchor;
    d.axis = axis;
    return d;
}

TEST(Joints, BodyFrameAnchorsAndAxesMapBackToTheScene) {
    Bodies w({{0, 0, 0}, {2, 0, 0}});
    const JointDesc d =
        joint(JointType::Hinge, 0, 1, {1, 0.2f, 0}, glm::normalize(glm::vec3(1, 1, 0)));
    const std::vector<Joint> joints = makeJoints(std::vector<JointDesc>{d}, w.poses);
    ASSERT_EQ(joints.size(), 1u);
    EXPECT_NEAR(glm::length(w.point(0, joints[0].anchorA) - d.anchor), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(w.point(1, joints[0].anchorB) - d.anchor), 0.0f, 1e-6f);
    float linear = 1.0f, angular = 1.0f;
    jointError(joints[0], w.poses, linear, angular);
    EXPECT_NEAR(linear, 0.0f, 1e-6f);
    EXPECT_NEAR(angular, 0.0f, 1e-3f);
    for (const glm::vec3& p : joints[0].perpB)
        EXPECT_NEAR(glm::dot(p, glm::vec3(d.axis)), 0.0f, 1e-6f);
}

TEST(Joints, JoinedPairsAreSortedAndUnique) {
    Bodies w({{0, 0, 0}, {2, 0, 0}, {4, 0, 0}});
    const std::vector<JointDesc> descs = {joint(JointType::Ball, 2, 1, {3, 0, 0}),
                                          joint(JointType::Ball, 0, 1, {1, 0, 0}),
                                          joint(JointType::Hinge, 1, 0, {1, 0, 0})};
    const std::vector<BodyPair> pairs = joinedPairs(descs);
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0], (BodyPair{0, 1}));
    EXPECT_EQ(pairs[1], (BodyPair{1, 2}));
}

// The rows ask the anchors for the relative speed that cancels the parting their turns alone
// cause over the step, (w h) x ((w h) x r) / 2: after the step's motion they still meet to third
// order in w h. Rows asking for no relative speed would leave the anchor off by (w h)^2 r / 2
// after the step, for the projection to take out of the speed.
TEST(Joints, BallBlockKeepsTheAnchorsTogetherThroughTheStepAndKeepsMomentum) {
    const float h = 1.0f / 60.0f;
    Bodies w({{0, 0, 0}, {2, 0, 0}});
    std::vector<Joint> joints =
        makeJoints(std::vector<JointDesc>{joint(JointType::Ball, 0, 1, {1, 0, 0})}, w.poses);
    w.solver.velocity[0].linear = toLanes({-1, 2, 0});
    w.solver.velocity[1].linear = toLanes({3, 0, 1});
    w.solver.velocity[1].angular = toLanes({0, 0, 2});
    prepareJoints(joints, w.poses, w.solver, true, h);
    for (int i = 0; i < 10; ++i) solveJointVelocity(joints[0], w.solver, 1.0f);
    const float apart = glm::length(w.pointAfter(1, joints[0].anchorB, h) -
                                    w.pointAfter(0, joints[0].anchorA, h));
    EXPECT_LT(apart, 2e-5f) << "m apart after the step";
    const glm::vec3 p = fromLanes(w.solver.velocity[0].linear + w.solver.velocity[1].linear);
    EXPECT_NEAR(glm::length(p - glm::vec3(2, 2, 1)), 0.0f, 1e-5f);
    EXPECT_NE(joints[0].pointImpulse, glm::vec3(0.0f));
}

TEST(Joints, HingeBlockKeepsOnlyTheTurnAboutItsAxis) {
    Bodies w({{0, 0, 0}, {2, 0, 0}});
    std::vector<Joint> joints = makeJoints(
        std::vector<JointDesc>{joint(JointType::Hinge, 2, 1, {1, 0, 0}, {0, 1, 0})}, w.poses);
    w.solver.velocity[1].angular = toLanes({1, 3, -2});
    const float h = 1.0f / 60.0f;
    prepareJoints(joints, w.poses, w.solver, true, h);
    for (int i = 0; i < 10; ++i) solveJointVelocity(joints[0], w.solver, 1.0f);
    const glm::vec3 omega = fromLanes(w.solver.velocity[1].angular);
    EXPECT_NEAR(omega.x, 0.0f, 1e-4f);
    EXPECT_NEAR(omega.z, 0.0f, 1e-4f);
    EXPECT_GT(omega.y, 0.0f);
    // The static body stays; body 1's anchor comes round to it at the end of the step.
    EXPECT_LT(glm::length(w.pointAfter(1, joints[0].anchorB, h) - glm::vec3(1, 0, 0)), 1e-6f);
}

// The projection is judged by test::JointGapProbe, from the joint's description and the poses
// alone, not by the report of the code under test: closed to the projection's tolerances
// (RUBBLE_JOINT_LINEAR_TOLERANCE, m, and RUBBLE_JOINT_ANGULAR_TOLERANCE, rad).
TEST(JointPositions, NewtonStepsCloseAnOpenJoint) {
    Bodies w({{0, 0, 0}, {2, 0, 0}});
    const std::vector<JointDesc> descs{joint(JointType::Hinge, 0, 1, {1, 0, 0})};
    const std::vector<Joint> joints = makeJoints(descs, w.poses);
    const test::JointGapProbe probe(descs, w.poses);
    // Pull body 1 away by 5 cm and turn it 5 degrees off the hinge axis.
    w.poses[1].position = shared::vec4(2.05f, 0.03f, 0);
    w.poses[1].orientation = toFloat4(glm::angleAxis(0.0872665f, glm::vec3(1, 0, 0)));
    const glm::vec3 centre = (toVec3(w.poses[0].position) + toVec3(w.poses[1].position)) * 0.5f;
    const JointGroups groups = groupJoints(joints, w.masses);
    JointPositionScratch scratch;
    const test::JointGap before = probe.at(w.poses);
    const JointPositionReport r =
        correctJointPositions(joints, groups, w.masses, w.poses, 8, scratch);
    const test::JointGap closed = probe.at(w.poses);
    EXPECT_GT(before.linear, 0.05);
    EXPECT_GT(before.angular, 0.08);
    EXPECT_LT(closed.linear, RUBBLE_JOINT_LINEAR_TOLERANCE);
    EXPECT_LT(closed.angular, RUBBLE_JOINT_ANGULAR_TOLERANCE);
    EXPECT_LE(r.iterations, 4);
    // Equal masses moved equally: the common centre of mass stays.
    const glm::vec3 after = (toVec3(w.poses[0].position) + toVec3(w.poses[1].position)) * 0.5f;
    EXPECT_NEAR(glm::length(after - centre), 0.0f, 1e-4f);
}

TEST(JointPositions, GroupsFollowMovingBodiesOnly) {
    // 0-1-2 chained, 3 alone on the static wall (4), and 2 also on the wall: the wall joins
    // nothing, so the groups are {0-1, 1-2, 2-wall} and {3-wall}.
    Bodies w({{0, 0, 0}, {2, 0, 0}, {4, 0, 0}, {6, 0, 0}});
    const std::vector<JointDesc> descs = {
        joint(JointType::Ball, 0, 1, {1, 0, 0}), joint(JointType::Ball, 3, 4, {6, 1, 0}),
        joint(JointType::Ball, 1, 2, {3, 0, 0}), joint(JointType::Ball, 2, 4, {5, 0, 0})};
    const JointGroups g = groupJoints(makeJoints(descs, w.poses), w.masses);
    ASSERT_EQ(g.start.size(), 3u);
    EXPECT_EQ(std::vector<std::uint32_t>(g.members.begin(), g.members.begin() + g.start[1]),
              (std::vector<std::uint32_t>{0, 2, 3}));
    EXPECT_EQ(std::vector<std::uint32_t>(g.members.begin() + g.start[1], g.members.end()),
              (std::vector<std::uint32_t>{1}));
}

TEST(JointPositions, LargeGroupsFallBackToJointByJoint) {
    // A chain of 70 bodies has 207 rows, more than kDirectRowLimit: joint by joint, 20 sweeps
    // close its 1 cm gaps to a two-hundredth.
    std::vector<glm::vec3> centres;
    for (int i = 0; i < 70; ++i) centres.push_back({2.0f * float(i), 0, 0});
    Bodies w(centres);
    std::vector<JointDesc> descs;
    for (std::uint32_t i = 0; i + 1 < 70; ++i)
        descs.push_back(joint(JointType::Ball, i, i + 1, {2.0f * float(i) + 1.0f, 0, 0}));
    const std::vector<Joint> joints = makeJoints(descs, w.poses);
    ASSERT_GT(joints.size() * 3, kDirectRowLimit);
    const test::JointGapProbe probe(descs, w.poses);
    for (std::size_t i = 1; i < centres.size(); i += 2) w.poses[i].position.y += 0.01f;
    const double before = probe.at(w.poses).linear;
    JointPositionScratch scratch;
    correctJointPositions(joints, groupJoints(joints, w.masses), w.masses, w.poses, 20, scratch);
    EXPECT_NEAR(before, 0.01, 1e-6);
    EXPECT_LT(probe.at(w.poses).linear, 0.005 * before);
}

} // namespace
} // namespace rubble
