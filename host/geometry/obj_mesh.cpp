// host/geometry/obj_mesh.cpp: tinyobjloader wrapped into TriangleMesh; its messages become Errors.
#include "host/geometry/obj_mesh.h"

#include <filesystem>

#include <tiny_obj_loader.h>

#include "host/core/math.h"

namespace rubble {

Result<TriangleMesh> loadObjMesh(const std::string& path, float scale, const std::string& where) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return makeError(ErrorKind::BadInput, where, "mesh file not found: " + path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) {
        std::string why = reader.Error();
        while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
        return makeError(ErrorKind::BadInput, where,
                         "cannot read the OBJ mesh " + path + (why.empty() ? "" : ": " + why));
    }
    const auto& coords = reader.GetAttrib().vertices;
    TriangleMesh mesh;
    mesh.vertices.reserve(coords.size() / 3);
    for (std::size_t i = 0; i + 2 < coords.size(); i += 3) {
        const glm::vec3 v = glm::vec3(coords[i], coords[i + 1], coords[i + 2]) * scale;
        if (!isFinite(v))
            return makeError(ErrorKind::BadInput, where,
                             path + ": vertex " + std::to_string(i / 3 + 1) + " is not finite");
        mesh.vertices.push_back(v);
    }
    for (const auto& shape : reader.GetShapes()) {
        const auto& indices = shape.mesh.indices;
        for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
            const int a = indices[i].vertex_index, b = indices[i + 1].vertex_index,
                      c = indices[i + 2].vertex_index;
            const int n = int(mesh.vertices.size());
            if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n)
                return makeError(ErrorKind::BadInput, where,
                                 path + ": a face refers to a vertex that does not exist");
            mesh.triangles.emplace_back(a, b, c);
        }
    }
    if (mesh.triangles.empty())
        return makeError(ErrorKind::BadInput, where, path + ": the mesh has no faces");
    return mesh;
}

} // namespace rubble
