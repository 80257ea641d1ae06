// host/geometry/obj_mesh.cpp: OBJ meshes: the text checked line by line (tinyobjloader reads what
// does not parse as 0), then read by tinyobjloader into a TriangleMesh; its messages become
// Errors.
#include "host/geometry/obj_mesh.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

#include <tiny_obj_loader.h>

#include "host/core/math.h"

namespace rubble {
namespace {

// Statements of the OBJ format other than v, vt, vn and f: read or ignored by tinyobjloader,
// never turned into numbers of the mesh.
constexpr std::string_view kOtherStatements[] = {
    "vp",    "l",     "p",        "o",          "g",         "s",    "mg",    "usemtl",
    "mtllib", "maplib", "usemap",  "lod",        "shadow_obj", "trace_obj", "bevel", "c_interp",
    "d_interp", "cstype", "deg",  "bmat",       "step",      "curv", "curv2", "surf",
    "parm",  "trim",  "hole",     "scrv",       "sp",        "end",  "con",   "call",
    "csh"};

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// The next whitespace-separated token of `line` from `at`, or an empty view at its end.
std::string_view nextToken(std::string_view line, std::size_t& at) {
    while (at < line.size() && isSpace(line[at])) ++at;
    const std::size_t start = at;
    while (at < line.size() && !isSpace(line[at])) ++at;
    return line.substr(start, at - start);
}

// The token as a whole decimal number (a leading '+' allowed), or nothing.
std::optional<double> parseReal(std::string_view token) {
    if (!token.empty() && token[0] == '+') token.remove_prefix(1);
    double v = 0.0;
    const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
    if (r.ec != std::errc() || r.ptr != token.data() + token.size()) return std::nullopt;
    return v;
}

// The token as a whole integer (a leading '+' allowed) that fits 32 bits, or nothing.
std::optional<std::int64_t> parseIndex(std::string_view token) {
    if (!token.empty() && token[0] == '+') token.remove_prefix(1);
    std::int32_t v = 0;
    const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
    if (r.ec != std::errc() || r.ptr != token.data() + token.size()) return std::nullopt;
    return v;
}

std::string quoted(std::string_view token) {
    std::string s(token.substr(0, 24));
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    return "\"" + s + (token.size() > 24 ? "...\"" : "\"");
}

// Checks the text of an OBJ file before tinyobjloader reads it: every v, vt and vn line holds
// the right count of finite numbers that fit a float, every f line three or more vertex
// references of whole, non-zero indices that name an existing vertex (and texture coordinate
// and normal), and every other line is a comment or an OBJ statement. BadInput at `where`
// naming the file and the line.
Status checkObjText(std::string_view text, const std::string& path, const std::string& where) {
    std::size_t line = 0, vertices = 0, texcoords = 0, normals = 0, triangles = 0;
    // The largest positive index of each kind and its line: they may be defined after the face.
    std::int64_t largest[3] = {0, 0, 0};
    std::size_t largestLine[3] = {0, 0, 0};
    auto fail = [&](std::size_t at, const std::string& message) -> Status {
        return makeError(ErrorKind::BadInput, where,
                         path + " line " + std::to_string(at) + ": " + message);
    };
    for (std::size_t start = 0; start < text.size();) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        const std::string_view l = text.substr(start, end - start);
        start = end + 1;
        ++line;
        std::size_t at = 0;
        const std::string_view keyword = nextToken(l, at);
        if (keyword.empty() || keyword[0] == '#') continue;
        if (keyword == "v" || keyword == "vt" || keyword == "vn") {
            std::size_t count = 0;
            for (std::string_view t = nextToken(l, at); !t.empty(); t = nextToken(l, at)) {
                if (t[0] == '#') break;
                const std::optional<double> v = parseReal(t);
                if (!v) return fail(line, "the coordinate " + quoted(t) + " is not a number");
                if (!std::isfinite(*v) || !std::isfinite(float(*v)))
                    return fail(line, "the coordinate " + quoted(t) +
                                          " is not a finite single-precision number");
                ++count;
            }
            const bool fits = keyword == "v"    ? count == 3 || count == 4 || count == 6 || count == 7
                              : keyword == "vt" ? count >= 1 && count <= 3
                                                : count == 3;
            if (!fits)
                return fail(line, "a \"" + std::string(keyword) + "\" line takes " +
                                      (keyword == "v"    ? "x y z (and w, or r g b)"
                                       : keyword == "vt" ? "u (v w)"
                                                         : "x y z") +
                                      ", got " + std::to_string(count) + " numbers");
            std::size_t& defined = keyword == "v" ? vertices : keyword == "vt" ? texcoords : normals;
            ++defined;
            if (keyword == "v" && vertices > kMaxMeshVertices)
                return fail(line, "the mesh has more than " + std::to_string(kMaxMeshVertices) +
                                      " vertices, the most rubble builds a shape from");
            continue;
        }
        if (keyword == "f") {
            std::size_t corners = 0;
            for (std::string_view t = nextToken(l, at); !t.empty(); t = nextToken(l, at)) {
                if (t[0] == '#') break;
                // v, v/vt, v//vn or v/vt/vn.
                std::string_view parts[3];
                std::size_t partCount = 0;
                for (std::size_t from = 0; partCount < 3;) {
                    const std::size_t slash = t.find('/', from);
                    parts[partCount++] = t.substr(from, slash == std::string_view::npos
                                                            ? std::string_view::npos
                                                            : slash - from);
                    if (slash == std::string_view::npos) break;
                    from = slash + 1;
                    if (partCount == 3) return fail(line, "the face corner " + quoted(t) +
                                                              " has more than three parts");
                }
                const std::size_t counts[3] = {vertices, texcoords, normals};
                static const char* const names[3] = {"vertex", "texture coordinate", "normal"};
                static const char* const plurals[3] = {"vertices", "texture coordinates",
                                                       "normals"};
                for (std::size_t k = 0; k < partCount; ++k) {
                    if (parts[k].empty() && k > 0) continue; // v//vn
                    const std::optional<std::int64_t> i = parseIndex(parts[k]);
                    const std::string corner =
                        "the face corner " + quoted(t) +
                        (partCount > 1 ? " (its " + std::string(names[k]) + " index)" : "");
                    if (!i || *i == 0)
                        return fail(line, corner + " is not an index: a whole number other than "
                                                   "0, from -2147483648 to 2147483647");
                    if (*i < 0 && std::size_t(-*i) > counts[k])
                        return fail(line, corner + " counts back " + std::to_string(-*i) +
                                              " from the " + std::to_string(counts[k]) + " " +
                                              plurals[k] + " defined so far");
                    if (*i > largest[k]) {
                        largest[k] = *i;
                        largestLine[k] = line;
                    }
                }
                ++corners;
            }
            if (corners < 3)
                return fail(line, "a face needs at least 3 corners, got " + std::to_string(corners));
            triangles += corners - 2;
            if (triangles > kMaxMeshTriangles)
                return fail(line, "the mesh has more than " + std::to_string(kMaxMeshTriangles) +
                                      " triangles, the most rubble builds a shape from");
            continue;
        }
        bool known = false;
        for (std::string_view k : kOtherStatements) known = known || keyword == k;
        if (!known) return fail(line, "unknown OBJ statement " + quoted(keyword));
    }
    const std::size_t defined[3] = {vertices, texcoords, normals};
    const char* names[3] = {"vertex", "texture coordinate", "normal"};
    for (int k = 0; k < 3; ++k)
        if (std::size_t(largest[k]) > defined[k])
            return fail(largestLine[k], "a face refers to " + std::string(names[k]) + " " +
                                            std::to_string(largest[k]) + ", and the file defines " +
                                            std::to_string(defined[k]));
    return {};
}

} // namespace

Result<TriangleMesh> loadObjMesh(const std::string& path, float scale, const std::string& where) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return makeError(ErrorKind::BadInput, where, "mesh file not found: " + path);
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (ec || bytes > kMaxObjBytes)
        return makeError(ErrorKind::BadInput, where,
                         path + ": " +
                             (ec ? "cannot read the file size"
                                 : "the file holds " + std::to_string(bytes) +
                                       " bytes, more than the " + std::to_string(kMaxObjBytes) +
                                       " an OBJ mesh may have"));
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) return makeError(ErrorKind::BadInput, where, "cannot read the OBJ mesh " + path);
    return parseObjMesh(std::move(text).str(), path, scale, where);
}

Result<TriangleMesh> parseObjMesh(const std::string& obj, const std::string& path, float scale,
                                  const std::string& where) {
    if (obj.size() > kMaxObjBytes)
        return makeError(ErrorKind::BadInput, where,
                         path + ": the text holds " + std::to_string(obj.size()) +
                             " bytes, more than the " + std::to_string(kMaxObjBytes) +
                             " an OBJ mesh may have");
    RUBBLE_TRY(checkObjText(obj, path, where));

    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    // Materials are not read: a mesh is a shape, its surface comes from the scene.
    if (!reader.ParseFromString(obj, "", config)) {
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
                             path + ": vertex " + std::to_string(i / 3 + 1) +
                                 " is not finite once scaled by " + std::to_string(scale));
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
