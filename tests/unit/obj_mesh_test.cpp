// tests/unit/obj_mesh_test.cpp: OBJ text that tinyobjloader would read as zeros or accept is
// refused naming the file and the line; good files read as before.
#include <set>

#include <gtest/gtest.h>

#include "host/geometry/obj_mesh.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// A tetrahedron: the base of every case.
const std::string kTetrahedron = "# a tetrahedron\n"
                                 "v 0 0 0\n"
                                 "v 1 0 0\n"
                                 "v 0 1 0\n"
                                 "v 0 0 1\n"
                                 "f 1 3 2\n"
                                 "f 1 2 4\n"
                                 "f 1 4 3\n"
                                 "f 2 3 4\n";

Result<TriangleMesh> loadText(const std::string& text, const std::string& name) {
    const std::string file = test::tempDir("obj_" + name) + "/mesh.obj";
    test::writeText(file, text);
    return loadObjMesh(file, 1.0f, "scene.json: shapes.m.file");
}

struct BadObj {
    const char* name;
    const char* find;    // a fragment of kTetrahedron
    const char* replace; // what goes in its place
    const char* message; // expected after "mesh.obj line N: "
    int line;
};

const BadObj kBadObjs[] = {
    {"NanCoordinate", "v 1 0 0", "v nan 0 0", "the coordinate \"nan\" is not a finite", 3},
    {"InfCoordinate", "v 0 1 0", "v 0 -inf 0", "the coordinate \"-inf\" is not a finite", 4},
    {"BeyondFloat", "v 0 1 0", "v 0 1e39 0", "the coordinate \"1e39\" is not a finite single-precision number", 4},
    {"GarbageBytes", "v 0 0 1", "v 0 0 1\x01\xfe", "the coordinate \"1??\" is not a number", 5},
    {"TwoCoordinates", "v 1 0 0", "v 2 0", "a \"v\" line takes x y z (and w, or r g b), got 2", 3},
    {"FiveCoordinates", "v 1 0 0", "v 1 0 0 1 1", "a \"v\" line takes x y z (and w, or r g b), got 5 numbers", 3},
    {"FractionalIndex", "f 1 3 2", "f 1.5 3 2", "the face corner \"1.5\" is not an index", 6},
    {"OverflowingIndex", "f 1 3 2", "f 1 3 4294967298", "the face corner \"4294967298\" is not an index", 6},
    {"ZeroIndex", "f 1 2 4", "f 1 0 4", "the face corner \"0\" is not an index", 7},
    {"MissingVertex", "f 2 3 4", "f 2 3 5", "a face refers to vertex 5, and the file defines 4", 9},
    {"CountsBackTooFar", "f 2 3 4", "f -1 -2 -5", "the face corner \"-5\" counts back 5 from the 4 vertices", 9},
    {"BadNormalIndex", "f 1 4 3", "f 1//x 4 3", "the face corner \"1//x\" (its normal index) is not an index", 8},
    {"MissingNormal", "f 1 4 3", "f 1//1 4//1 3//1", "a face refers to normal 1, and the file defines 0", 8},
    {"TwoCorners", "f 1 4 3", "f 1 4", "a face needs at least 3 corners, got 2", 8},
    {"UnknownStatement", "# a tetrahedron", "\x89PNG", "unknown OBJ statement \"?PNG\"", 1},
};

class ObjErrors : public ::testing::TestWithParam<BadObj> {};

TEST_P(ObjErrors, RefusedNamingTheLine) {
    const BadObj& c = GetParam();
    std::string text = kTetrahedron;
    const std::size_t at = text.find(c.find);
    ASSERT_NE(at, std::string::npos) << c.find;
    text.replace(at, std::string(c.find).size(), c.replace);
    const Result<TriangleMesh> mesh = loadText(text, c.name);
    ASSERT_FALSE(mesh.ok()) << "accepted";
    EXPECT_EQ(mesh.error().kind, ErrorKind::BadInput);
    const std::string described = mesh.error().describe();
    EXPECT_NE(described.find("scene.json: shapes.m.file: "), std::string::npos) << described;
    EXPECT_NE(described.find("mesh.obj line " + std::to_string(c.line) + ": " + c.message),
              std::string::npos)
        << described;
}

INSTANTIATE_TEST_SUITE_P(BadText, ObjErrors, ::testing::ValuesIn(kBadObjs),
                         [](const ::testing::TestParamInfo<BadObj>& i) { return std::string(i.param.name); });

TEST(ObjMesh, ReadsPolygonsCommentsAndOtherStatements) {
    // A unit cube as quads, with groups, smoothing, normals, texture coordinates, a material
    // line, relative indices, a trailing comment, CRLF line ends and '+' signs.
    const std::string cube = "mtllib cube.mtl\r\no cube\r\n"
                             "v 0 0 0\r\nv +1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
                             "v 0 0 1\r\nv 1 0 1\r\nv 1 1 1\r\nv 0 1 1 # last\r\n"
                             "vt 0 0\r\nvn 0 0 -1\r\ng sides\r\ns off\r\nusemtl stone\r\n"
                             "f 1/1/1 4/1/1 3/1/1 2/1/1\r\nf 5 6 7 8\r\nf 1 2 6 5\r\n"
                             "f 2 3 7 6\r\nf 3 4 8 7\r\nf -4 -8 -5 -1\r\n";
    const Result<TriangleMesh> mesh = loadText(cube, "cube");
    ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
    EXPECT_EQ(mesh->vertices.size(), 8u);
    EXPECT_EQ(mesh->triangles.size(), 12u);
    EXPECT_EQ(mesh->vertices[1], glm::vec3(1, 0, 0));
    // f -4 -8 -5 -1 is f 5 1 4 8: its two triangles cover vertices 4, 0, 3, 7 (from 0).
    std::set<std::uint32_t> corners;
    for (int t : {10, 11})
        for (int k = 0; k < 3; ++k) corners.insert(mesh->triangles[std::size_t(t)][k]);
    EXPECT_EQ(corners, (std::set<std::uint32_t>{0, 3, 4, 7}));
}

// The scene's mesh keeps its mass: what tinyobjloader reads of the good file is unchanged.
TEST(ObjMesh, ExampleMeshesStillRead) {
    for (const char* file : {"rock.obj", "l_block.obj", "bowl.obj"}) {
        const Result<TriangleMesh> mesh = loadObjMesh(
            std::string(RUBBLE_SOURCE_DIR) + "/scenes/meshes/" + file, 1.0f, file);
        EXPECT_TRUE(mesh.ok()) << file << ": " << mesh.error().describe();
    }
}

} // namespace
} // namespace rubble
