// host/gpu/hull_data.h: the shapes flattened for the device's SAT narrow phase
// (host/collision/hull_data.h), refused where the device cannot clip a hull's faces;
// host/gpu/sat.cpp uploads them.
#pragma once

#include <span>

#include "host/collision/hull_data.h"
#include "rubble/error.h"

namespace rubble::gpu {

using rubble::hullArraysOf;
using rubble::HullData;

/// flattenHulls for the device. Errors: NotSupported naming the shape when a hull face has more
/// than RUBBLE_HULL_MAX_FACE_VERTICES vertices (the device clips faces in private memory).
Result<HullData> flattenShapes(std::span<const Shape> shapes);

} // namespace rubble::gpu
