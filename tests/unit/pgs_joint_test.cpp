// tests/unit/pgs_joint_test.cpp: the device's joint code (rubble/shared/pgs_joint.h, compiled for
// the host here) against the CPU's host/dynamics/joints and joint_positions on random bodies,
// poses and velocities: the same rows, velocity updates and one Newton projection step.
#include "rubble/shared/pgs_joint.h"

#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "host/core/math.h"
#include "host/dynamics/joint_positions.h"
#include "host/dynamics/joints.h"
#include "support/joint_gap.h"

namespace rubble {
namespace {

// Two boxes of random size, mass, pose and velocity joined near their touching corners; body a
// is static when `staticA`.
struct JointCase {
    std::vector<shared::BodyMass> masses;
    std::vector<shared::BodyPose> poses;
    std::vector<shared::BodyVelocity> velocities;
    std::vector<Joint> joints;
};

glm::quat randomTurn(std::mt19937& rng, float angle) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(1e-3f));
    return glm::angleAxis(angle * u(rng), axis);
}

JointCase makeCase(std::mt19937& rng, JointType type, bool staticA) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), size(0.1f, 0.6f), mass(0.5f, 8.0f);
    JointCase c;
    for (int body = 0; body < 2; ++body) {
        shared::BodyMass m{};
        const glm::vec3 h(size(rng), size(rng), size(rng));
        const float kg = mass(rng);
        const glm::mat3 inertia(glm::vec3(kg / 3.0f * (h.y * h.y + h.z * h.z), 0, 0),
                                glm::vec3(0, kg / 3.0f * (h.x * h.x + h.z * h.z), 0),
                                glm::vec3(0, 0, kg / 3.0f * (h.x * h.x + h.y * h.y)));
        if (body == 0 && staticA) {
            m.flags = RUBBLE_BODY_STATIC;
        } else {
            m.mass = kg;
            m.inverseMass = 1.0f / kg;
            m.inertiaBody = toShared(inertia);
            m.inverseInertiaBody = toShared(glm::inverse(inertia));
        }
        c.masses.push_back(m);
        const glm::vec3 x =
            glm::vec3(0, 1, 0) * float(body) + 0.2f * glm::vec3(u(rng), u(rng), u(rng));
        c.poses.push_back({toFloat4(x), toFloat4(randomTurn(rng, 3.0f))});
        shared::BodyVelocity v{};
        if (!(body == 0 && staticA)) {
            v.linear = toFloat4(2.0f * glm::vec3(u(rng), u(rng), u(rng)));
            v.angular = toFloat4(3.0f * glm::vec3(u(rng), u(rng), u(rng)));
        }
        c.velocities.push_back(v);
    }
    JointDesc d;
    d.type = type;
    d.a = 0;
    d.b = 1;
    d.anchor = glm::vec3(0, 0.5f, 0) + 0.1f * glm::vec3(u(rng), u(rng), u(rng));
    d.axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0, 0, 1.5f));
    const std::vector<JointDesc> descs{d};
    c.joints = makeJoints(descs, c.poses);
    // The joint drifts: b moves and turns a little away from where it was joined.
    shared::BodyPose& pb = c.poses[1];
    pb.position = toFloat4(toVec3(pb.position) + 0.03f * glm::vec3(u(rng), u(rng), u(rng)));
    pb.orientation = toFloat4(randomTurn(rng, 0.05f) * toQuat(pb.orientation));
    return c;
}

glm::vec4 toVec4(shared::float4 q) {
    return glm::vec4(q.x, q.y, q.z, q.w);
}

shared::JacobiBody jacobiBody(const shared::BodyMass& m, const shared::BodyPose& p) {
    shared::BodyMass mass = m;
    if (m.flags & RUBBLE_BODY_STATIC) mass = shared::wallMassItem(m);
    return shared::jacobiBodyItem(mass, p.orientation);
}

bool sameBits(glm::vec3 a, glm::vec3 b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}
bool sameBits(glm::vec4 a, glm::vec4 b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

void expectNear(glm::vec3 device, glm::vec3 cpu, float tolerance, const char* what, int trial) {
    const float scale = std::max(1.0f, glm::length(cpu));
    EXPECT_LE(glm::length(device - cpu), tolerance * scale)
        << what << " (trial " << trial << "): device " << device.x << " " << device.y << " "
        << device.z << ", cpu " << cpu.x << " " << cpu.y << " " << cpu.z;
}

// Rows and one velocity update of each joint type, a free pair and one with a static body a.
TEST(PgsJoint, RowsAndVelocityUpdatesMatchTheCpu) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
        const JointType type = trial % 2 ? JointType::Hinge : JointType::Ball;
        JointCase c = makeCase(rng, type, trial % 4 >= 2);
        SolverBodies bodies;
        gatherSolverMasses(c.masses, c.poses, bodies);
        gatherSolverVelocities(c.velocities, bodies);
        prepareJoints(c.joints, c.poses, bodies, true, 1.0f / 60.0f);

        const shared::PgsJoint dj = sharedJoint(c.joints[0]);
        const shared::JacobiBody ja = jacobiBody(c.masses[0], c.poses[0]);
        const shared::JacobiBody jb = jacobiBody(c.masses[1], c.poses[1]);
        shared::PgsJointRow row{};
        row = shared::prepareJointItem(dj, row, c.poses[0], c.poses[1], ja, jb, 1, 1.0f / 60.0f);
        const Joint& j = c.joints[0];
        expectNear(toVec3(row.ra), j.ra, 1e-6f, "ra", trial);
        expectNear(toVec3(row.rb), j.rb, 1e-6f, "rb", trial);
        const glm::mat3 pointMass = toMat3(row.pointMass);
        for (int k = 0; k < 3; ++k)
            expectNear(pointMass[k], j.pointMass[k], 1e-4f, "pointMass", trial);
        if (type == JointType::Hinge) {
            expectNear(toVec3(row.turn[0]), j.turn[0], 1e-6f, "turn[0]", trial);
            expectNear(toVec3(row.turn[1]), j.turn[1], 1e-6f, "turn[1]", trial);
        }
        // The effective masses to the bit: both sides invert as glm::inverse does (the
        // determinant's reciprocal times each cofactor), so that a world of joints steps the
        // same on the device as on the CPU until the position projections (float against
        // double) part.
        for (int k = 0; k < 3; ++k)
            EXPECT_TRUE(sameBits(pointMass[k], j.pointMass[k])) << "pointMass, trial " << trial;
        if (type == JointType::Hinge) {
            const float device[4] = {row.turnMass.x, row.turnMass.y, row.turnMass.z,
                                     row.turnMass.w};
            const float cpu[4] = {j.turnMass[0][0], j.turnMass[1][0], j.turnMass[0][1],
                                  j.turnMass[1][1]};
            EXPECT_EQ(std::memcmp(device, cpu, sizeof device), 0) << "turnMass, trial " << trial;
        }

        // One update from the same velocities.
        shared::BodyVelocityPair v{c.velocities[0], c.velocities[1]};
        const shared::PgsJointUpdate u = shared::solveJointItem(v, dj, row, ja, jb, 1.0f);
        solveJointVelocity(c.joints[0], bodies, 1.0f);
        for (int body = 0; body < 2; ++body) {
            const shared::BodyVelocity& d = body == 0 ? u.v.a : u.v.b;
            if (!bodies.moves(std::uint32_t(body))) continue;
            expectNear(toVec3(d.linear), fromLanes(bodies.velocity[body].linear), 1e-4f, "linear",
                       trial);
            expectNear(toVec3(d.angular), fromLanes(bodies.velocity[body].angular), 1e-4f,
                       "angular", trial);
            EXPECT_TRUE(sameBits(toVec3(d.linear), fromLanes(bodies.velocity[body].linear)))
                << "linear, trial " << trial;
            EXPECT_TRUE(sameBits(toVec3(d.angular), fromLanes(bodies.velocity[body].angular)))
                << "angular, trial " << trial;
        }
        expectNear(toVec3(u.pointImpulse), j.pointImpulse, 1e-4f, "point impulse", trial);
    }
}

// One Newton step of the position projection of a single joint: the CPU's poses to the bit
// (the shared code factors in JointReal, double here and on a device with fp64, as the CPU's
// solveRows).
TEST(PgsJoint, ProjectionStepMatchesTheCpu) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 200; ++trial) {
        const JointType type = trial % 2 ? JointType::Hinge : JointType::Ball;
        JointCase c = makeCase(rng, type, trial % 4 >= 2);
        std::vector<shared::BodyPose> cpu = c.poses;
        const JointGroups groups = groupJoints(c.joints, c.masses);
        JointPositionScratch scratch;
        correctJointPositions(c.joints, groups, c.masses, cpu, 1, scratch);

        int moved = 0;
        const shared::PosePair out = shared::projectJointItem(
            sharedJoint(c.joints[0]), c.poses[0], c.poses[1], jacobiBody(c.masses[0], c.poses[0]),
            jacobiBody(c.masses[1], c.poses[1]), &moved);
        EXPECT_EQ(moved, 1) << trial;
        const shared::BodyPose device[2] = {out.a, out.b};
        for (int body = 0; body < 2; ++body) {
            EXPECT_TRUE(sameBits(toVec3(device[body].position), toVec3(cpu[body].position)))
                << "position, trial " << trial;
            EXPECT_TRUE(sameBits(toVec4(device[body].orientation), toVec4(cpu[body].orientation)))
                << "orientation, trial " << trial;
        }
        // And the step reduces the error as the CPU's does.
        float before = 0, after = 0, angular = 0;
        jointError(c.joints[0], c.poses, before, angular);
        const std::vector<shared::BodyPose> devicePoses{out.a, out.b};
        jointError(c.joints[0], devicePoses, after, angular);
        EXPECT_LT(after, before) << trial;
    }
}

// A group projected as one: a chain of six boxes from a static pin, ball and hinge joints in
// turn, drifted apart; the device's projection of the whole group against the CPU's over up to
// 20 Newton steps, both factoring in double: the same poses to the bit, and the joints closed
// to the projection's tolerances.
TEST(PgsJoint, GroupProjectionMatchesTheCpu) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), mass(0.5f, 4.0f);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<shared::BodyMass> masses;
        std::vector<shared::BodyPose> poses;
        shared::BodyMass pin{};
        pin.flags = RUBBLE_BODY_STATIC;
        masses.push_back(pin);
        poses.push_back({shared::vec4(0, 6, 0), shared::make4(0, 0, 0, 1)});
        std::vector<JointDesc> descs;
        for (int i = 1; i <= 6; ++i) {
            shared::BodyMass m{};
            const float kg = mass(rng);
            const glm::vec3 h(0.1f, 0.4f, 0.1f);
            const glm::mat3 inertia(glm::vec3(kg / 3.0f * (h.y * h.y + h.z * h.z), 0, 0),
                                    glm::vec3(0, kg / 3.0f * (h.x * h.x + h.z * h.z), 0),
                                    glm::vec3(0, 0, kg / 3.0f * (h.x * h.x + h.y * h.y)));
            m.mass = kg;
            m.inverseMass = 1.0f / kg;
            m.inertiaBody = toShared(inertia);
            m.inverseInertiaBody = toShared(glm::inverse(inertia));
            masses.push_back(m);
            poses.push_back({shared::vec4(0, 6.0f - 1.0f * float(i) + 0.5f, 0),
                             toFloat4(randomTurn(rng, 0.2f))});
            JointDesc d;
            d.type = i % 2 ? JointType::Ball : JointType::Hinge;
            d.a = std::uint32_t(i - 1);
            d.b = std::uint32_t(i);
            d.anchor = glm::vec3(0, 6.0f - 1.0f * float(i - 1), 0);
            d.axis = glm::vec3(1, 0, 0);
            descs.push_back(d);
        }
        const std::vector<Joint> joints = makeJoints(descs, poses);
        const test::JointGapProbe probe(descs, poses);
        // Drift: every link moved and turned a little.
        for (std::size_t i = 1; i < poses.size(); ++i) {
            poses[i].position =
                toFloat4(toVec3(poses[i].position) + 0.02f * glm::vec3(u(rng), u(rng), u(rng)));
            poses[i].orientation = toFloat4(randomTurn(rng, 0.05f) * toQuat(poses[i].orientation));
        }
        std::vector<shared::BodyPose> cpu = poses, device = poses;
        JointPositionScratch scratch;
        correctJointPositions(joints, groupJoints(joints, masses), masses, cpu, 20, scratch);

        std::vector<shared::PgsJoint> deviceJoints;
        std::vector<std::uint32_t> members, flags;
        for (std::uint32_t j = 0; j < joints.size(); ++j) {
            deviceJoints.push_back(sharedJoint(joints[j]));
            members.push_back(j);
        }
        for (const shared::BodyMass& m : masses) flags.push_back(m.flags);
        std::vector<shared::JointPositionRow> rows(5 * joints.size());
        std::vector<shared::JointReal> matrix(rows.size() * rows.size()), solution(rows.size());
        std::vector<shared::float4> dx(poses.size(), shared::vec4(0, 0, 0)), dq = dx;
        const int steps = shared::projectJointGroupItem(
            members.data(), std::uint32_t(members.size()), deviceJoints.data(), masses.data(),
            flags.data(), device.data(), rows.data(), matrix.data(), solution.data(), dx.data(),
            dq.data(), 20);
        for (std::size_t i = 0; i < poses.size(); ++i) {
            EXPECT_TRUE(sameBits(toVec3(device[i].position), toVec3(cpu[i].position)))
                << "position, trial " << trial;
            EXPECT_TRUE(sameBits(toVec4(device[i].orientation), toVec4(cpu[i].orientation)))
                << "orientation, trial " << trial;
        }
        // Closed to the projection's tolerances, as measured from the joints' descriptions (not
        // by the projection's own report).
        const test::JointGap before = probe.at(poses), after = probe.at(device);
        EXPECT_GT(before.linear, 0.01) << trial;
        EXPECT_LT(after.linear, RUBBLE_JOINT_LINEAR_TOLERANCE) << trial;
        EXPECT_LT(after.angular, RUBBLE_JOINT_ANGULAR_TOLERANCE) << trial;
        EXPECT_GT(steps, 1) << trial;
    }
}

} // namespace
} // namespace rubble
