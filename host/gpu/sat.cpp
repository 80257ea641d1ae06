// host/gpu/sat.cpp: the SAT method's hulls on the device and the dispatch of its narrow phase
// (kernels/sat.cl, collideShapes), with the per-pair feature cache kept between steps. The CPU
// twin is SatCollision::narrowPhase (host/collision/sat_collision.cpp).
#include "host/gpu/sat.h"

#include "host/gpu/hull_data.h"

namespace rubble::gpu {

Status DeviceShapes::create(StageQueue& q, std::span<const Shape> worldShapes,
                            std::span<const std::uint32_t> bodyShapes) {
    const Context& c = q.c();
    Result<HullData> hulls = flattenShapes(worldShapes);
    RUBBLE_TRY(hulls);
    RUBBLE_TRY(upload(c, shapes, hulls->shapes));
    RUBBLE_TRY(upload(c, vertices, hulls->vertices));
    RUBBLE_TRY(upload(c, vertexEdges, hulls->vertexEdges));
    RUBBLE_TRY(upload(c, neighbourStart, hulls->neighbourStart));
    RUBBLE_TRY(upload(c, neighbours, hulls->neighbours));
    RUBBLE_TRY(upload(c, halfEdges, hulls->halfEdges));
    RUBBLE_TRY(upload(c, faces, hulls->faces));
    RUBBLE_TRY(upload(c, faceEdges, hulls->faceEdges));
    RUBBLE_TRY(upload(c, edges, hulls->edges));
    // Uploaded once: the levels are static.
    const LevelData levelData = flattenLevels(worldShapes);
    RUBBLE_TRY(upload(c, levelOf, levelData.levelOf));
    RUBBLE_TRY(upload(c, levels, levelData.levels));
    RUBBLE_TRY(upload(c, levelNodes, levelData.nodes));
    RUBBLE_TRY(upload(c, levelTriangles, levelData.triangles));
    return upload(c, shapeOf, bodyShapes);
}

Status collideShapes(StageQueue& q, const DeviceBodies& b, const DeviceShapes& s,
                     const Buffer& spin, const Buffer& boxes, PairStore& pairs, float dt) {
    const Context& c = q.c();
    // The contact count and the largest depth are this stage's.
    for (const cl_uint slot : {RUBBLE_STATUS_CONTACTS, RUBBLE_STATUS_PENETRATION})
        RUBBLE_TRY(
            fillRange(c, q.status(), 0u, slot * sizeof(cl_uint), sizeof(cl_uint), &q.profile()));
    const cl_float step = dt;
    return Dispatch(c, KernelId::CollideShapes, &q.profile())
        .with([&](Dispatch& d) { pairs.bindCurrent(d); })
        .with([&](Dispatch& d) { pairs.bindPrevious(d); })
        .arg(pairs.previous.features)
        .arg(s.shapes)
        .arg(s.shapeOf)
        .arg(b.poses)
        .arg(b.velocities)
        .arg(b.flags)
        .arg(spin)
        .arg(s.vertices)
        .arg(s.vertexEdges)
        .arg(s.neighbourStart)
        .arg(s.neighbours)
        .arg(s.halfEdges)
        .arg(s.faces)
        .arg(s.faceEdges)
        .arg(s.edges)
        .arg(s.levelOf)
        .arg(s.levels)
        .arg(s.levelNodes)
        .arg(s.levelTriangles)
        .arg(boxes)
        .arg(step)
        .arg(pairs.current.features)
        .arg(pairs.manifolds)
        .arg(pairs.previousOf)
        .arg(q.status())
        .run(pairs.strideItems(q), c.workSizes().pairGroup);
}

} // namespace rubble::gpu
