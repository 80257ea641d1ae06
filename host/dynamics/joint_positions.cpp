// host/dynamics/joint_positions.cpp: Newton projection of joint groups onto their constraints,
// after stage 7.
#include "host/dynamics/joint_positions.h"

#include <algorithm>
#include <cmath>

#include "host/core/assert.h"
#include "host/core/union_find.h"
#include "host/core/math.h"
#include "rubble/shared/pgs_joint.h"

namespace rubble {
namespace {

// The tolerances and limits are the device's too (rubble/shared/pgs_joint.h): a group is done
// when every point row is within the linear tolerance, m, and every hinge row within the
// angular one (the cosine between the axis and a perpendicular, about the angle in rad); one
// projection moves an anchor by at most the linear correction, m, and turns a body by at most
// the angular one, rad; pivots below the pivot tolerance's fraction of the largest diagonal entry
// are redundant rows, left out.
constexpr float kLinearTolerance = RUBBLE_JOINT_LINEAR_TOLERANCE;
constexpr float kAngularTolerance = RUBBLE_JOINT_ANGULAR_TOLERANCE;
constexpr float kMaxLinearCorrection = RUBBLE_JOINT_MAX_LINEAR_CORRECTION;
constexpr float kMaxAngularCorrection = RUBBLE_JOINT_MAX_ANGULAR_CORRECTION;
using shared::JointReal;
constexpr double kPivotTolerance = RUBBLE_JOINT_PIVOT_TOLERANCE;

glm::vec3 rotate(const shared::BodyPose& pose, glm::vec3 v) {
    return toVec3(shared::quatRotate(pose.orientation, toFloat4(v)));
}

struct BodyInverse {
    float mass = 0;
    glm::mat3 inertia{0.0f};
};

BodyInverse inverseOf(const shared::BodyMass& m, const shared::BodyPose& pose) {
    BodyInverse r;
    if (!isAwakeDynamic(m)) return r;
    r.mass = m.inverseMass;
    r.inertia = toMat3(shared::inverseInertiaWorldItem(m, pose.orientation));
    return r;
}

// Appends a joint's rows at the current poses: three point rows along the world axes, and for a
// hinge the two rows a_1 . b_2, a_1 . c_2. Returns false when neither body moves.
bool appendRows(const Joint& j, std::span<const shared::BodyMass> masses,
                std::span<const shared::BodyPose> poses, std::vector<PositionRow>& rows) {
    const shared::BodyPose& pa = poses[j.a];
    const shared::BodyPose& pb = poses[j.b];
    const BodyInverse ia = inverseOf(masses[j.a], pa), ib = inverseOf(masses[j.b], pb);
    if (ia.mass == 0.0f && ib.mass == 0.0f) return false;
    auto push = [&](float error, glm::vec3 linear, glm::vec3 angularA, glm::vec3 angularB) {
        PositionRow r;
        r.a = j.a;
        r.b = j.b;
        r.error = error;
        r.linearA = -linear;
        r.angularA = angularA;
        r.linearB = linear;
        r.angularB = angularB;
        r.moveA = r.linearA * ia.mass;
        r.turnA = ia.inertia * r.angularA;
        r.moveB = r.linearB * ib.mass;
        r.turnB = ib.inertia * r.angularB;
        rows.push_back(r);
    };
    const glm::vec3 ra = rotate(pa, j.anchorA), rb = rotate(pb, j.anchorB);
    glm::vec3 c = (toVec3(pb.position) + rb) - (toVec3(pa.position) + ra);
    const float size = glm::length(c);
    if (size > kMaxLinearCorrection) c *= kMaxLinearCorrection / size;
    for (int k = 0; k < 3; ++k) {
        glm::vec3 e(0.0f);
        e[k] = 1.0f;
        // C_k = (p_b - p_a) . e_k: turning a by theta moves p_a by theta x r_a.
        push(c[k], e, -glm::cross(ra, e), glm::cross(rb, e));
    }
    if (j.type == JointType::Hinge) {
        const glm::vec3 a1 = rotate(pa, j.axisA);
        for (int k = 0; k < 2; ++k) {
            const glm::vec3 p2 = rotate(pb, j.perpB[k]);
            // d(a_1 . p_2) = (theta_a - theta_b) . (a_1 x p_2)
            const glm::vec3 turn = glm::cross(a1, p2);
            push(glm::dot(a1, p2), glm::vec3(0.0f), turn, -turn);
        }
    }
    return true;
}

// J_i M^-1 J_j^T over the bodies the two rows share.
double coupling(const PositionRow& x, const PositionRow& y) {
    double k = 0.0;
    if (x.a == y.a) k += glm::dot(x.linearA, y.moveA) + glm::dot(x.angularA, y.turnA);
    if (x.a == y.b) k += glm::dot(x.linearA, y.moveB) + glm::dot(x.angularA, y.turnB);
    if (x.b == y.a) k += glm::dot(x.linearB, y.moveA) + glm::dot(x.angularB, y.turnA);
    if (x.b == y.b) k += glm::dot(x.linearB, y.moveB) + glm::dot(x.angularB, y.turnB);
    return k;
}

// Solves K lambda = -C for the rows by LDL^T (K is symmetric positive semi-definite; redundant
// rows get no impulse). The result goes to scratch.solution.
void solveRows(JointPositionScratch& scratch) {
    const std::vector<PositionRow>& rows = scratch.rows;
    const std::size_t n = rows.size();
    std::vector<double>& k = scratch.matrix;
    std::vector<double>& x = scratch.solution;
    k.assign(n * n, 0.0);
    x.resize(n);
    double largest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j <= i; ++j) k[i * n + j] = coupling(rows[i], rows[j]);
        largest = std::max(largest, k[i * n + i]);
        x[i] = -double(rows[i].error);
    }
    // Lower triangle: L below the diagonal, D on it; a zero D marks a dropped row.
    for (std::size_t j = 0; j < n; ++j) {
        double d = k[j * n + j];
        for (std::size_t p = 0; p < j; ++p) d -= k[j * n + p] * k[j * n + p] * k[p * n + p];
        if (d <= kPivotTolerance * largest) d = 0.0;
        k[j * n + j] = d;
        for (std::size_t i = j + 1; i < n; ++i) {
            double l = k[i * n + j];
            for (std::size_t p = 0; p < j; ++p) l -= k[i * n + p] * k[j * n + p] * k[p * n + p];
            k[i * n + j] = d > 0.0 ? l / d : 0.0;
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t p = 0; p < i; ++p) x[i] -= k[i * n + p] * x[p];
    for (std::size_t i = 0; i < n; ++i) x[i] = k[i * n + i] > 0.0 ? x[i] / k[i * n + i] : 0.0;
    for (std::size_t i = n; i-- > 0;)
        for (std::size_t p = i + 1; p < n; ++p) x[i] -= k[p * n + i] * x[p];
}

// Moves the bodies by M^-1 J^T lambda, one pose update per body.
void applySolution(std::span<shared::BodyPose> poses, JointPositionScratch& scratch) {
    std::vector<glm::vec3>& dx = scratch.deltaPosition;
    std::vector<glm::vec3>& dq = scratch.deltaRotation;
    for (std::size_t i = 0; i < scratch.rows.size(); ++i) {
        const PositionRow& r = scratch.rows[i];
        const float lambda = float(scratch.solution[i]);
        dx[r.a] += r.moveA * lambda;
        dq[r.a] += r.turnA * lambda;
        dx[r.b] += r.moveB * lambda;
        dq[r.b] += r.turnB * lambda;
    }
    // A step that would turn a body further than kMaxAngularCorrection is shortened as a whole:
    // far from the solution the linearisation overshoots.
    float largestTurn = 0.0f;
    for (const PositionRow& r : scratch.rows)
        largestTurn = std::max({largestTurn, glm::length(dq[r.a]), glm::length(dq[r.b])});
    const float scale =
        largestTurn > kMaxAngularCorrection ? kMaxAngularCorrection / largestTurn : 1.0f;
    for (const PositionRow& r : scratch.rows) {
        for (const std::uint32_t body : {r.a, r.b}) {
            dx[body] *= scale;
            dq[body] *= scale;
            if (dx[body] == glm::vec3(0.0f) && dq[body] == glm::vec3(0.0f)) continue;
            shared::BodyPose& pose = poses[body];
            pose.position = toFloat4(toVec3(pose.position) + dx[body]);
            pose.orientation = shared::quatIntegrate(pose.orientation, toFloat4(dq[body]), 1.0f);
            dx[body] = glm::vec3(0.0f);
            dq[body] = glm::vec3(0.0f);
        }
    }
}

// Largest point-row and hinge-row errors among the rows.
void rowErrors(std::span<const PositionRow> rows, float& linear, float& angular) {
    linear = angular = 0.0f;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const bool point = rows[i].linearB != glm::vec3(0.0f);
        float& worst = point ? linear : angular;
        worst = std::max(worst, std::abs(rows[i].error));
    }
}

// One Newton step on the given joints together; returns false when they are within tolerance.
bool projectOnce(std::span<const Joint> joints, std::span<const std::uint32_t> members,
                 std::span<const shared::BodyMass> masses, std::span<shared::BodyPose> poses,
                 JointPositionScratch& scratch) {
    scratch.rows.clear();
    for (const std::uint32_t j : members) appendRows(joints[j], masses, poses, scratch.rows);
    float linear = 0.0f, angular = 0.0f;
    rowErrors(scratch.rows, linear, angular);
    if (linear <= kLinearTolerance && angular <= kAngularTolerance) return false;
    solveRows(scratch);
    applySolution(poses, scratch);
    return true;
}

} // namespace

JointGroups groupJoints(std::span<const Joint> joints, std::span<const shared::BodyMass> masses) {
    // Union-find over moving bodies; each joint joins its group by its first moving body.
    UnionFind sets(masses.size());
    auto dynamic = [&](std::uint32_t i) { return masses[i].inverseMass > 0.0f; };
    for (const Joint& j : joints)
        if (dynamic(j.a) && dynamic(j.b)) sets.unite(j.a, j.b);
    // Joints sorted by their group's root, then by index: deterministic.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed;
    for (std::uint32_t j = 0; j < joints.size(); ++j)
        keyed.push_back({sets.find(dynamic(joints[j].a) ? joints[j].a : joints[j].b), j});
    std::sort(keyed.begin(), keyed.end());
    JointGroups g;
    for (std::size_t i = 0; i < keyed.size(); ++i) {
        if (i == 0 || keyed[i].first != keyed[i - 1].first) g.start.push_back(std::uint32_t(i));
        g.members.push_back(keyed[i].second);
    }
    g.start.push_back(std::uint32_t(keyed.size()));
    return g;
}

JointPositionReport correctJointPositions(std::span<const Joint> joints, const JointGroups& groups,
                                          std::span<const shared::BodyMass> masses,
                                          std::span<shared::BodyPose> poses, int maxIterations,
                                          JointPositionScratch& scratch) {
    JointPositionReport report;
    if (joints.empty()) return report;
    scratch.deltaPosition.resize(poses.size(), glm::vec3(0.0f));
    scratch.deltaRotation.resize(poses.size(), glm::vec3(0.0f));
    auto measure = [&](float& linear, float& angular) {
        linear = angular = 0.0f;
        for (const Joint& j : joints) {
            if (!isAwakeDynamic(masses[j.a]) && !isAwakeDynamic(masses[j.b])) continue;
            float l = 0.0f, a = 0.0f;
            jointError(j, poses, l, a);
            linear = std::max(linear, l);
            angular = std::max(angular, a);
        }
    };
    float unused = 0.0f;
    measure(report.linearErrorBefore, unused);

    for (std::size_t g = 0; g + 1 < groups.start.size(); ++g) {
        const std::span<const std::uint32_t> members(groups.members.data() + groups.start[g],
                                                     groups.start[g + 1] - groups.start[g]);
        std::size_t rows = 0;
        for (const std::uint32_t j : members) rows += joints[j].type == JointType::Hinge ? 5 : 3;
        int it = 0;
        for (; it < maxIterations; ++it) {
            if (rows <= kDirectRowLimit) {
                if (!projectOnce(joints, members, masses, poses, scratch)) break;
            } else {
                // Too large to factor: one joint at a time (non-linear Gauss-Seidel).
                bool moved = false;
                for (std::size_t m = 0; m < members.size(); ++m)
                    moved =
                        projectOnce(joints, members.subspan(m, 1), masses, poses, scratch) || moved;
                if (!moved) break;
            }
        }
        report.iterations = std::max(report.iterations, it);
    }
    measure(report.linearErrorAfter, report.angularErrorAfter);
    return report;
}

} // namespace rubble
