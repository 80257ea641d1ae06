// host/gpu/hull_data.cpp: the device's limit on hull faces, over the flattening of
// host/collision/hull_data.cpp.
#include "host/gpu/hull_data.h"

#include <string>

namespace rubble::gpu {

Result<HullData> flattenShapes(std::span<const Shape> shapes) {
    for (std::size_t index = 0; index < shapes.size(); ++index) {
        const Shape& s = shapes[index];
        if (!collidesAsHull(s.type)) continue;
        for (std::uint32_t f = 0; f < s.halfEdge.faceCount(); ++f) {
            const auto n = std::uint32_t(faceVertices(s.halfEdge, f).size());
            if (n > RUBBLE_HULL_MAX_FACE_VERTICES)
                return makeError(ErrorKind::NotSupported,
                                 "shapes[" + std::to_string(index) + "]" +
                                     (s.name.empty() ? "" : " (" + s.name + ")"),
                                 "a face of its hull has " + std::to_string(n) +
                                     " vertices; the device's SAT narrow phase clips faces "
                                     "of at most " +
                                     std::to_string(RUBBLE_HULL_MAX_FACE_VERTICES) +
                                     " (collide it with particles, or simplify the hull)");
        }
    }
    return flattenHulls(shapes);
}

} // namespace rubble::gpu
