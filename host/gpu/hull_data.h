// host/gpu/hull_data.h: the shapes flattened for the device's SAT narrow phase
// (host/collision/hull_data.h), refused where the device cannot clip a hull's faces, and the
// static level meshes' triangles and hierarchies;
// host/gpu/sat.cpp uploads them.
#pragma once

#include <span>
#include <vector>

#include "host/collision/hull_data.h"
#include "rubble/error.h"
#include "rubble/shared/level_contact.h"

namespace rubble::gpu {

using rubble::hullArraysOf;
using rubble::HullData;

/// The static level meshes of a world's shapes flattened for the device
/// (rubble/shared/level_contact.h): each level's hierarchy and its triangles in leaf order.
struct LevelData {
    std::vector<std::uint32_t> levelOf; ///< per shape: its index in `levels`, or RUBBLE_NO_LEVEL
    std::vector<shared::LevelShape> levels;
    std::vector<shared::LevelNode> nodes;
    std::vector<shared::MeshTriangle> triangles;
};

/// The level meshes of the shapes that have one (Shape::level).
LevelData flattenLevels(std::span<const Shape> shapes);

/// flattenHulls for the device. Errors: NotSupported naming the shape when a hull face has more
/// than RUBBLE_HULL_MAX_FACE_VERTICES vertices (the device clips faces in private memory).
Result<HullData> flattenShapes(std::span<const Shape> shapes);

} // namespace rubble::gpu
