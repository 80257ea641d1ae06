// host/gpu/sat.cpp: the SAT method's device arrays (hulls flattened once per world, per-body and
// pair arrays) and the dispatch of its narrow phase (kernels/sat.cl, collideShapes), with the
// per-pair feature cache kept between steps. The CPU twin is SatCollision::narrowPhase
// (host/collision/sat_collision.cpp).
#include <algorithm>

#include "host/core/assert.h"
#include "host/core/union_find.h"
#include "host/gpu/hull_data.h"
#include "host/gpu/pipeline.h"

namespace rubble::gpu {
namespace {

// The bits of a grid of at least 4096 columns and one per four bodies: columns of two mean box
// widths over one layer of bodies hold about that many, and a pile holds more. Columns widened
// to fit cost longer sweeps, not more entries; fewer key bits cost fewer passes of the sort.
std::uint32_t gridBitsFor(std::uint32_t bodies) {
    const std::uint64_t cells = std::max<std::uint64_t>(4096, std::uint64_t(bodies) / 4);
    std::uint32_t bits = 1;
    while ((std::uint64_t(1) << bits) < cells) ++bits;
    return bits;
}

// The sweep keys' bits below a column key of gridBits: at least 12 (steps of 1/4096 of the
// boxes' range), filling the sort's last digit, within 32 bits in all.
std::uint32_t sweepBitsFor(std::uint32_t gridBits) {
    const std::uint32_t digit = RUBBLE_SORT_DIGIT_BITS;
    const std::uint32_t total =
        std::min<std::uint32_t>(32, (gridBits + 12 + digit - 1) / digit * digit);
    return total - gridBits;
}

} // namespace

Status Pipeline::createSat(const PipelineInput& in) {
    const Context& c = *context_;
    SatBuffers& s = sat_;
    Result<HullData> hulls = flattenShapes(in.shapes);
    RUBBLE_TRY(hulls);
    RUBBLE_TRY(upload(c, s.shapes, hulls->shapes));
    RUBBLE_TRY(upload(c, s.vertices, hulls->vertices));
    RUBBLE_TRY(upload(c, s.vertexEdges, hulls->vertexEdges));
    RUBBLE_TRY(upload(c, s.neighbourStart, hulls->neighbourStart));
    RUBBLE_TRY(upload(c, s.neighbours, hulls->neighbours));
    RUBBLE_TRY(upload(c, s.halfEdges, hulls->halfEdges));
    RUBBLE_TRY(upload(c, s.faces, hulls->faces));
    RUBBLE_TRY(upload(c, s.faceEdges, hulls->faceEdges));
    RUBBLE_TRY(upload(c, s.edges, hulls->edges));

    const std::uint32_t n = bodies_.count;
    RUBBLE_TRY(upload(c, s.shapeOf, in.bodies.shapeOf));
    std::vector<cl_uint> planes;
    for (std::uint32_t i = 0; i < n; ++i) {
        RUBBLE_ASSERT(in.bodies.shapeOf[i] < in.shapes.size());
        if (in.shapes[in.bodies.shapeOf[i]].type == ShapeType::Plane) planes.push_back(i);
    }
    s.planeCount = std::uint32_t(planes.size());
    RUBBLE_TRY(upload(c, s.planes, planes));
    std::vector<shared::BodyPairRecord> joined;
    for (const BodyPair& p : in.joined) joined.push_back({std::min(p.a, p.b), std::max(p.a, p.b)});
    std::sort(joined.begin(), joined.end(),
              [](const auto& x, const auto& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); });
    s.joinedCount = std::uint32_t(joined.size());
    RUBBLE_TRY(upload(c, s.joined, joined));

    // Per body.
    RUBBLE_TRY(s.boxes.reserve(c.context(), n * sizeof(shared::BodyBox)));
    RUBBLE_TRY(s.spin.reserve(c.context(), n * sizeof(cl_float)));
    RUBBLE_TRY(s.broadFlags.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(s.bodyCount.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(s.bodyStart.reserve(c.context(), (n + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(s.cursor.reserve(c.context(), (n + 1) * sizeof(cl_uint)));
    RUBBLE_TRY(s.large.reserve(c.context(), n * sizeof(cl_uint)));
    // The columns: at most 4 entries (2 x 2 columns) per body.
    s.gridBits = gridBitsFor(n);
    s.sweepBits = sweepBitsFor(s.gridBits);
    RUBBLE_TRY(
        s.partials.reserve(c.context(), c.workSizes().sortItems * sizeof(shared::GridPartial)));
    RUBBLE_TRY(s.grid.reserve(c.context(), sizeof(shared::GridParams)));
    for (Buffer* b : {&s.keys, &s.values, &s.keysAlt, &s.valuesAlt})
        RUBBLE_TRY(b->reserve(c.context(), 4 * std::size_t(n) * sizeof(cl_uint)));
    RUBBLE_TRY(s.cellBoxes.reserve(c.context(), 4 * std::size_t(n) * sizeof(shared::BodyBox)));

    s.enabled = true;
    // Pairs: a first guess of four per body.
    return createPairArrays(in, std::max<std::uint32_t>(1024, 4 * n));
}

Status Pipeline::createPairArrays(const PipelineInput& in, std::uint32_t guess) {
    const Context& c = *context_;
    SatBuffers& s = sat_;
    const std::uint32_t n = bodies_.count;
    // Last step's set is empty.
    for (PairSet* set : {&s.current, &s.previous}) {
        RUBBLE_TRY(set->count.reserve(c.context(), 2 * sizeof(cl_uint)));
        RUBBLE_TRY(fill(c, set->count, 0u, 2 * sizeof(cl_uint)));
        RUBBLE_TRY(set->pairs.reserve(c.context(), sizeof(shared::BodyPairRecord)));
        RUBBLE_TRY(set->features.reserve(c.context(), sizeof(shared::PairCache)));
        RUBBLE_TRY(set->impulseCount.reserve(c.context(), sizeof(cl_uint)));
        RUBBLE_TRY(set->impulses.reserve(c.context(), 4 * sizeof(shared::PgsImpulse)));
        RUBBLE_TRY(set->keys.reserve(c.context(), sizeof(shared::ParticleContactKey)));
    }
    // PGS, per body.
    RUBBLE_TRY(pgs_.pushed.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(pgs_.push.reserve(c.context(), n * sizeof(shared::BodyVelocity)));
    RUBBLE_TRY(createJoints(in));
    // Both sets at the first guess, so that the first steps' swaps reallocate nothing: a buffer
    // released while queued commands still read it is legal, but Oclgrind 21.10 then sees the
    // buffer that replaces it as never written (every later read of last step's features was
    // reported).
    RUBBLE_TRY(setPairCapacity(guess));
    std::swap(s.current, s.previous);
    RUBBLE_TRY(setPairCapacity(guess));
    std::swap(s.current, s.previous); // last step's set holds none (its count is 0)
    return {};
}

Status Pipeline::setPairCapacity(std::uint32_t capacity) {
    const Context& c = *context_;
    SatBuffers& s = sat_;
    const std::size_t n = capacity;
    s.current.capacity = capacity;
    RUBBLE_TRY(s.current.pairs.reserve(c.context(), n * sizeof(shared::BodyPairRecord)));
    RUBBLE_TRY(s.current.features.reserve(c.context(), n * sizeof(shared::PairCache)));
    RUBBLE_TRY(s.found.reserve(c.context(), n * sizeof(shared::BodyPairRecord)));
    RUBBLE_TRY(s.manifolds.reserve(c.context(), n * sizeof(shared::ContactManifold)));
    RUBBLE_TRY(s.previousOf.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(s.current.impulseCount.reserve(c.context(), n * sizeof(cl_uint)));
    RUBBLE_TRY(s.current.impulses.reserve(c.context(), 4 * n * sizeof(shared::PgsImpulse)));
    RUBBLE_TRY(pgs_.pairRows.reserve(c.context(), n * sizeof(cl_uint)));
    if (particlePgs_)
        RUBBLE_TRY(s.current.keys.reserve(c.context(), n * sizeof(shared::ParticleContactKey)));
    // Last step's set keeps its size: the next narrow phase reads it before it changes.
    return {};
}

Status Pipeline::keepPairFeatures() {
    RUBBLE_ASSERT(pairPgs());
    // Particles carry nothing: their sets' second count word stays 0 (keptPairsItem).
    if (sat_.enabled) RUBBLE_TRY(carryStillPairs());
    std::swap(sat_.current, sat_.previous);
    // The set to fill next holds as many pairs as the one kept. Growing it (after a pair
    // overflow) reallocates buffers that this step's queued kernels read as last step's: they
    // run first.
    const std::uint32_t capacity = std::max(sat_.current.capacity, sat_.previous.capacity);
    if (capacity > sat_.current.capacity) RUBBLE_TRY(finish());
    return setPairCapacity(capacity);
}

Status Pipeline::carryStillPairs() {
    const Context& c = *context_;
    SatBuffers& s = sat_;
    const std::uint32_t items = c.workSizes().sortItems;
    const std::size_t entries = std::size_t(s.previous.capacity) + 1;
    RUBBLE_TRY(s.carry.reserve(c.context(), entries * sizeof(cl_uint)));
    RUBBLE_TRY(s.place.reserve(c.context(), entries * sizeof(cl_uint)));
    RUBBLE_TRY(s.chunkCounts.reserve(c.context(), std::size_t(items) * sizeof(cl_uint)));
    RUBBLE_TRY(s.chunkStarts.reserve(c.context(), (std::size_t(items) + 1) * sizeof(cl_uint)));
    const cl_uint previousCapacity = s.previous.capacity;
    RUBBLE_TRY(Dispatch(c, KernelId::MarkStillPairs, &profile_)
                   .with([&](Dispatch& d) { bindPreviousPairs(d); })
                   .arg(s.previous.impulseCount)
                   .with([&](Dispatch& d) { bindPairs(d); })
                   .arg(bodies_.jacobi)
                   .arg(s.carry)
                   .arg(s.chunkCounts)
                   .arg(status_)
                   .run(items, RUBBLE_GROUP_SCAN));
    RUBBLE_TRY(exclusiveScan(s.chunkCounts, s.chunkStarts, items));
    RUBBLE_TRY(Dispatch(c, KernelId::PlaceStillPairs, &profile_)
                   .arg(previousCapacity)
                   .arg(s.previous.count)
                   .arg(s.carry)
                   .arg(s.chunkStarts)
                   .arg(s.place)
                   .run(items, RUBBLE_GROUP_SCAN));
    return Dispatch(c, KernelId::CarryStillPairs, &profile_)
        .with([&](Dispatch& d) { bindPreviousPairs(d); })
        .arg(s.previous.impulseCount)
        .arg(s.previous.impulses)
        .arg(s.carry)
        .arg(s.place)
        .with([&](Dispatch& d) { bindPairs(d); })
        .arg(s.current.impulseCount)
        .arg(s.current.impulses)
        .arg(status_)
        .run(strideItems(s.previous.capacity, c.workSizes().pairGroup), c.workSizes().pairGroup);
}

Status Pipeline::narrowPhase(float dt) {
    RUBBLE_ASSERT(sat_.enabled);
    const Context& c = *context_;
    SatBuffers& s = sat_;
    // The contact count and the largest depth are this stage's.
    for (const cl_uint slot : {RUBBLE_STATUS_CONTACTS, RUBBLE_STATUS_PENETRATION})
        RUBBLE_TRY(fillRange(c, status_, 0u, slot * sizeof(cl_uint), sizeof(cl_uint), &profile_));
    const cl_float step = dt;
    return Dispatch(c, KernelId::CollideShapes, &profile_)
        .with([&](Dispatch& d) { bindPairs(d); })
        .with([&](Dispatch& d) { bindPreviousPairs(d); })
        .arg(s.previous.features)
        .arg(s.shapes)
        .arg(s.shapeOf)
        .arg(bodies_.poses)
        .arg(bodies_.velocities)
        .arg(s.spin)
        .arg(s.vertices)
        .arg(s.vertexEdges)
        .arg(s.neighbourStart)
        .arg(s.neighbours)
        .arg(s.halfEdges)
        .arg(s.faces)
        .arg(s.faceEdges)
        .arg(s.edges)
        .arg(step)
        .arg(s.current.features)
        .arg(s.manifolds)
        .arg(s.previousOf)
        .arg(status_)
        .run(pairStrideItems(), c.workSizes().pairGroup);
}

Status Pipeline::uploadPairs(std::span<const BodyPair> pairs) {
    RUBBLE_ASSERT(sat_.enabled);
    const Context& c = *context_;
    if (pairs.size() > sat_.current.capacity)
        RUBBLE_TRY(setPairCapacity(std::uint32_t(pairs.size())));
    std::vector<shared::BodyPairRecord> records;
    records.reserve(pairs.size());
    for (const BodyPair& p : pairs) {
        RUBBLE_ASSERT(p.a < p.b && p.b < bodies_.count);
        records.push_back({p.a, p.b});
    }
    RUBBLE_TRY(upload(c, sat_.current.pairs, records));
    const cl_uint count = cl_uint(pairs.size());
    RUBBLE_TRY(upload(c, sat_.current.count, std::span<const cl_uint>(&count, 1)));
    return writeStatusSlot(RUBBLE_STATUS_PAIRS, count);
}

Result<std::vector<BodyPair>> Pipeline::downloadPairs() {
    Result<DeviceStatus> st = readStatus();
    RUBBLE_TRY(st);
    const Result<std::vector<shared::BodyPairRecord>> records = download<shared::BodyPairRecord>(
        *context_, sat_.current.pairs, std::min(st->pairs, sat_.current.capacity));
    RUBBLE_TRY(records);
    std::vector<BodyPair> pairs;
    pairs.reserve(records->size());
    for (const shared::BodyPairRecord& r : *records) pairs.push_back(BodyPair{r.a, r.b});
    return pairs;
}

Result<std::vector<shared::ContactManifold>> Pipeline::downloadManifolds() {
    Result<DeviceStatus> st = readStatus();
    RUBBLE_TRY(st);
    return download<shared::ContactManifold>(*context_, sat_.manifolds,
                                             std::min(st->pairs, sat_.current.capacity));
}

Result<std::vector<shared::PairCache>> Pipeline::downloadPairFeatures() {
    Result<DeviceStatus> st = readStatus();
    RUBBLE_TRY(st);
    return download<shared::PairCache>(*context_, sat_.current.features,
                                       std::min(st->pairs, sat_.current.capacity));
}

Result<std::vector<shared::BodyBox>> Pipeline::downloadBoxes() {
    return download<shared::BodyBox>(*context_, sat_.boxes, bodies_.count);
}

} // namespace rubble::gpu

namespace rubble::gpu {

Status Pipeline::createJoints(const PipelineInput& in) {
    const Context& c = *context_;
    PgsBuffers& g = pgs_;
    g.jointsHost.assign(in.joints.begin(), in.joints.end());
    g.jointCount = std::uint32_t(g.jointsHost.size());
    // A body joins the colorings when it is dynamic and the host does not move it.
    auto dynamic = [&](std::uint32_t i) {
        return in.bodies.masses[i].inverseMass > 0.0f && !kinematic_[i];
    };
    g.jointDynamicA.resize(g.jointCount);
    g.jointDynamicB.resize(g.jointCount);
    std::vector<std::uint8_t> jointed(bodies_.count, 0);
    for (std::uint32_t j = 0; j < g.jointCount; ++j) {
        const shared::PgsJoint& joint = g.jointsHost[j];
        RUBBLE_ASSERT(joint.a < bodies_.count && joint.b < bodies_.count);
        g.jointDynamicA[j] = dynamic(joint.a) ? 1 : 0;
        g.jointDynamicB[j] = dynamic(joint.b) ? 1 : 0;
        jointed[joint.a] = jointed[joint.b] = 1;
    }
    // Joint groups: dynamic bodies joined through dynamic bodies (union-find, as the CPU's
    // groupJoints), for the position projection and for sleeping together.
    UnionFind sets(bodies_.count);
    for (std::uint32_t j = 0; j < g.jointCount; ++j)
        if (g.jointDynamicA[j] && g.jointDynamicB[j])
            sets.unite(g.jointsHost[j].a, g.jointsHost[j].b);
    // The projection's groups: joints by their group's root, then by index. A group of at most
    // RUBBLE_JOINT_DIRECT_ROWS rows is projected as one; the joints of a larger one are
    // colored for the joint-by-joint sweeps.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed;
    for (std::uint32_t j = 0; j < g.jointCount; ++j) {
        const shared::PgsJoint& joint = g.jointsHost[j];
        keyed.push_back({sets.find(g.jointDynamicA[j] ? joint.a : joint.b), j});
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<shared::JointGroup> groups;
    std::vector<cl_uint> members;
    std::uint32_t rows = 0, matrix = 0;
    g.jointColoring.begin(bodies_.count);
    for (std::size_t first = 0; first < keyed.size();) {
        std::size_t last = first;
        std::uint32_t groupRows = 0;
        while (last < keyed.size() && keyed[last].first == keyed[first].first) {
            groupRows += g.jointsHost[keyed[last].second].type == RUBBLE_JOINT_HINGE ? 5 : 3;
            ++last;
        }
        if (groupRows <= RUBBLE_JOINT_DIRECT_ROWS) {
            groups.push_back(
                {std::uint32_t(members.size()), std::uint32_t(last - first), rows, matrix});
            for (std::size_t m = first; m < last; ++m) members.push_back(keyed[m].second);
            rows += groupRows;
            matrix += groupRows * groupRows;
        } else {
            for (std::size_t m = first; m < last; ++m) {
                const std::uint32_t j = keyed[m].second;
                g.jointColoring.add(j, g.jointsHost[j].a, g.jointsHost[j].b, g.jointDynamicA[j],
                                    g.jointDynamicB[j]);
            }
        }
        first = last;
    }
    g.jointColoring.finish();
    g.directGroupCount = std::uint32_t(groups.size());
    g.directMemberCount = std::uint32_t(members.size());
    g.directRowCount = rows;
    g.directMatrixCount = matrix;
    RUBBLE_TRY(upload(c, g.directGroups, groups));
    RUBBLE_TRY(upload(c, g.groupMembers, members));
    RUBBLE_TRY(g.positionRows.reserve(c.context(), rows * sizeof(shared::JointPositionRow)));
    const std::size_t real = c.workSizes().jointRealBytes();
    RUBBLE_TRY(g.positionMatrix.reserve(c.context(), matrix * real));
    RUBBLE_TRY(g.positionSolution.reserve(c.context(), rows * real));
    const std::size_t deltas = std::size_t(bodies_.count) * sizeof(shared::float4);
    for (Buffer* b : {&g.deltaPosition, &g.deltaRotation}) {
        RUBBLE_TRY(b->reserve(c.context(), deltas));
        RUBBLE_TRY(fill(c, *b, 0u, deltas));
    }
    // Sleep groups: the same, numbered by their lowest body.
    std::vector<cl_uint> bodies, groupOf;
    std::vector<std::uint32_t> groupOfRoot(bodies_.count, RUBBLE_NO_GROUP);
    g.jointGroupCount = 0;
    for (std::uint32_t i = 0; i < bodies_.count; ++i) {
        if (!jointed[i]) continue;
        bodies.push_back(i);
        if (!dynamic(i)) {
            groupOf.push_back(RUBBLE_NO_GROUP);
            continue;
        }
        std::uint32_t& group = groupOfRoot[sets.find(i)];
        if (group == RUBBLE_NO_GROUP) group = g.jointGroupCount++;
        groupOf.push_back(group);
    }
    g.jointBodyCount = std::uint32_t(bodies.size());
    RUBBLE_TRY(upload(c, g.joints, g.jointsHost));
    RUBBLE_TRY(upload(c, g.jointBodies, bodies));
    RUBBLE_TRY(upload(c, g.jointGroupOf, groupOf));
    RUBBLE_TRY(g.groupVotes.reserve(c.context(), g.jointGroupCount * sizeof(cl_uint)));
    RUBBLE_TRY(upload(c, g.jointOrder, g.jointColoring.order()));
    // No impulses yet.
    const std::size_t rowBytes = std::size_t(g.jointCount) * sizeof(shared::PgsJointRow);
    RUBBLE_TRY(g.jointRows.reserve(c.context(), rowBytes));
    RUBBLE_TRY(fill(c, g.jointRows, 0u, rowBytes));
    return g.jointMoved.reserve(c.context(), RUBBLE_JOINT_POSITION_ITERATIONS * sizeof(cl_uint));
}

} // namespace rubble::gpu
