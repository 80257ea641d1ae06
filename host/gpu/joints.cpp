// host/gpu/joints.cpp: a world's joints on the device: their buffers and groups at creation,
// each step's rows (prepareJoints) and the position projection (projectJointGroups,
// projectJoints, jointVelocities). Argument order is the kernel signature's.
#include "host/gpu/joints.h"

#include <algorithm>
#include <utility>

#include "host/core/assert.h"
#include "host/core/union_find.h"

namespace rubble::gpu {

Status DeviceJoints::create(StageQueue& q, std::span<const shared::PgsJoint> worldJoints,
                            BodiesView bodyArrays, std::span<const std::uint8_t> kinematic) {
    const Context& c = q.c();
    DeviceJoints& g = *this;
    const auto n = std::uint32_t(bodyArrays.count());
    g.host.assign(worldJoints.begin(), worldJoints.end());
    g.count = std::uint32_t(g.host.size());
    // A body joins the colorings when it is dynamic and the host does not move it.
    auto dynamic = [&](std::uint32_t i) {
        return bodyArrays.masses[i].inverseMass > 0.0f && !kinematic[i];
    };
    g.dynamicA.resize(g.count);
    g.dynamicB.resize(g.count);
    std::vector<std::uint8_t> jointed(n, 0);
    for (std::uint32_t j = 0; j < g.count; ++j) {
        const shared::PgsJoint& joint = g.host[j];
        RUBBLE_ASSERT(joint.a < n && joint.b < n);
        g.dynamicA[j] = dynamic(joint.a) ? 1 : 0;
        g.dynamicB[j] = dynamic(joint.b) ? 1 : 0;
        jointed[joint.a] = jointed[joint.b] = 1;
    }
    // Joint groups: dynamic bodies joined through dynamic bodies (union-find, as the CPU's
    // groupJoints), for the position projection and for sleeping together.
    UnionFind sets(n);
    for (std::uint32_t j = 0; j < g.count; ++j)
        if (g.dynamicA[j] && g.dynamicB[j]) sets.unite(g.host[j].a, g.host[j].b);
    // The projection's groups: joints by their group's root, then by index. A group of at most
    // RUBBLE_JOINT_DIRECT_ROWS rows is projected as one; the joints of a larger one are
    // colored for the joint-by-joint sweeps.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed;
    for (std::uint32_t j = 0; j < g.count; ++j) {
        const shared::PgsJoint& joint = g.host[j];
        keyed.push_back({sets.find(g.dynamicA[j] ? joint.a : joint.b), j});
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<shared::JointGroup> groups;
    std::vector<cl_uint> members;
    std::uint32_t directRows = 0, matrix = 0;
    g.coloring.begin(n);
    for (std::size_t first = 0; first < keyed.size();) {
        std::size_t last = first;
        std::uint32_t groupRows = 0;
        while (last < keyed.size() && keyed[last].first == keyed[first].first) {
            groupRows += g.host[keyed[last].second].type == RUBBLE_JOINT_HINGE ? 5 : 3;
            ++last;
        }
        if (groupRows <= RUBBLE_JOINT_DIRECT_ROWS) {
            groups.push_back(
                {std::uint32_t(members.size()), std::uint32_t(last - first), directRows, matrix});
            for (std::size_t m = first; m < last; ++m) members.push_back(keyed[m].second);
            directRows += groupRows;
            matrix += groupRows * groupRows;
        } else {
            for (std::size_t m = first; m < last; ++m) {
                const std::uint32_t j = keyed[m].second;
                g.coloring.add(j, g.host[j].a, g.host[j].b, g.dynamicA[j], g.dynamicB[j]);
            }
        }
        first = last;
    }
    g.coloring.finish();
    g.directGroupCount = std::uint32_t(groups.size());
    g.directMemberCount = std::uint32_t(members.size());
    g.directRowCount = directRows;
    g.directMatrixCount = matrix;
    RUBBLE_TRY(upload(c, g.directGroups, groups));
    RUBBLE_TRY(upload(c, g.groupMembers, members));
    RUBBLE_TRY(g.positionRows.reserve(c.context(), directRows * sizeof(shared::JointPositionRow)));
    const std::size_t real = c.workSizes().jointRealBytes();
    RUBBLE_TRY(g.positionMatrix.reserve(c.context(), matrix * real));
    RUBBLE_TRY(g.positionSolution.reserve(c.context(), directRows * real));
    const std::size_t deltas = std::size_t(n) * sizeof(shared::float4);
    for (Buffer* b : {&g.deltaPosition, &g.deltaRotation}) {
        RUBBLE_TRY(b->reserve(c.context(), deltas));
        RUBBLE_TRY(fill(c, *b, 0u, deltas));
    }
    // Sleep groups: the same, numbered by their lowest body.
    std::vector<cl_uint> jointedBodies, groupOfBody;
    std::vector<std::uint32_t> groupOfRoot(n, RUBBLE_NO_GROUP);
    g.groupCount = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!jointed[i]) continue;
        jointedBodies.push_back(i);
        if (!dynamic(i)) {
            groupOfBody.push_back(RUBBLE_NO_GROUP);
            continue;
        }
        std::uint32_t& group = groupOfRoot[sets.find(i)];
        if (group == RUBBLE_NO_GROUP) group = g.groupCount++;
        groupOfBody.push_back(group);
    }
    g.bodyCount = std::uint32_t(jointedBodies.size());
    RUBBLE_TRY(upload(c, g.joints, g.host));
    RUBBLE_TRY(upload(c, g.bodies, jointedBodies));
    RUBBLE_TRY(upload(c, g.groupOf, groupOfBody));
    RUBBLE_TRY(g.groupVotes.reserve(c.context(), g.groupCount * sizeof(cl_uint)));
    RUBBLE_TRY(upload(c, g.order, g.coloring.order()));
    // No impulses yet.
    const std::size_t rowBytes = std::size_t(g.count) * sizeof(shared::PgsJointRow);
    RUBBLE_TRY(g.rows.reserve(c.context(), rowBytes));
    RUBBLE_TRY(fill(c, g.rows, 0u, rowBytes));
    return g.moved.reserve(c.context(), RUBBLE_JOINT_POSITION_ITERATIONS * sizeof(cl_uint));
}

Status DeviceJoints::prepare(StageQueue& q, const DeviceBodies& b, bool warmStart, float dt) {
    if (count == 0) return {};
    const cl_uint jointCount = count, warm = warmStart ? 1u : 0u;
    const cl_float step = dt;
    return Dispatch(q.c(), KernelId::PrepareJoints, &q.profile())
        .arg(jointCount)
        .arg(joints)
        .arg(b.poses)
        .arg(b.jacobi)
        .arg(warm)
        .arg(step)
        .arg(rows)
        .run(jointCount, RUBBLE_GROUP_BODIES);
}

Status DeviceJoints::project(StageQueue& q, DeviceBodies& b) {
    if (count == 0) return {};
    const Context& c = q.c();
    Profile* profile = &q.profile();
    RUBBLE_TRY(fill(c, moved, 0u, RUBBLE_JOINT_POSITION_ITERATIONS * sizeof(cl_uint), profile));
    if (directGroupCount > 0) {
        const cl_uint groups = directGroupCount;
        const cl_int iterations = RUBBLE_JOINT_POSITION_ITERATIONS;
        RUBBLE_TRY(Dispatch(c, KernelId::ProjectJointGroups, profile)
                       .arg(groups)
                       .arg(directGroups)
                       .arg(groupMembers)
                       .arg(joints)
                       .arg(b.masses)
                       .arg(b.flags)
                       .arg(b.poses)
                       .arg(positionRows)
                       .arg(positionMatrix)
                       .arg(positionSolution)
                       .arg(deltaPosition)
                       .arg(deltaRotation)
                       .arg(iterations)
                       .run(groups, 1));
    }
    const std::span<const std::uint32_t> start = coloring.start();
    for (cl_uint sweep = 0; sweep < RUBBLE_JOINT_POSITION_ITERATIONS && coloring.colors() > 0;
         ++sweep) {
        for (std::uint32_t k = 0; k < coloring.colors(); ++k) {
            const cl_uint first = start[k], colorCount = start[k + 1] - start[k];
            RUBBLE_TRY(Dispatch(c, KernelId::ProjectJoints, profile)
                           .arg(first)
                           .arg(colorCount)
                           .arg(order)
                           .arg(joints)
                           .arg(b.masses)
                           .arg(b.flags)
                           .arg(b.poses)
                           .arg(sweep)
                           .arg(moved)
                           .run(colorCount, RUBBLE_GROUP_BODIES));
            // The joint, both bodies' masses, flags and poses (read and written).
            profile->setLastBytes(colorCount *
                                  (sizeof(shared::PgsJoint) + 2 * sizeof(shared::BodyMass) +
                                   2 * sizeof(cl_uint) + 4 * sizeof(shared::BodyPose)));
        }
    }
    const cl_uint jointed = bodyCount;
    return Dispatch(c, KernelId::JointVelocities, profile)
        .arg(jointed)
        .arg(bodies)
        .arg(b.masses)
        .arg(b.flags)
        .arg(b.poses)
        .arg(b.momenta)
        .arg(b.velocities)
        .run(jointed, RUBBLE_GROUP_BODIES);
}

} // namespace rubble::gpu
