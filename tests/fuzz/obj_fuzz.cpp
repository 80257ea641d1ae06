// tests/fuzz/obj_fuzz.cpp: libFuzzer target for the OBJ reader: any text is read as a mesh, and a
// mesh that reads is built into a shape (hull, half-edge mesh, mass properties). Nothing may
// crash, hang or leak; bad input must come back as an Error. Corpus: scenes/meshes/.
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/geometry/shape.h"
#include "host/geometry/obj_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    rubble::Result<rubble::TriangleMesh> mesh =
        rubble::parseObjMesh(text, "fuzz.obj", 1.0f, "shapes.m.file");
    if (!mesh) return 0;
    rubble::ShapeDesc d;
    d.name = "m";
    d.where = "fuzz.json: shapes.m";
    d.type = rubble::ShapeType::Mesh;
    d.points = std::move(mesh->vertices);
    d.triangles = std::move(mesh->triangles);
    rubble::Result<rubble::Shape> shape = rubble::buildShape(d);
    (void)shape;
    return 0;
}
