// host/scene/height_field.cpp: heightfield shapes: grids from JSON or a 16-bit greyscale PNG
// (stb_image from Debian's libstb, compiled here privately), into triangles.
#include "host/scene/height_field.h"

#include <cmath>
#include <filesystem>

#include "host/core/limits.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace rubble {
namespace {

// The largest value of a 16-bit sample: white, `height_scale` metres high.
constexpr float kPngWhite = 65535.0f;

Status readHeightsArray(const ObjectReader& s, HeightFieldDesc& grid) {
    const Json& rows = s.at("heights");
    if (!rows.is_array() || rows.empty() || !rows[0].is_array())
        return s.fail("heights", "expected an array of rows of heights, got " + brief(rows));
    grid.rows = std::uint32_t(rows.size());
    grid.columns = std::uint32_t(rows[0].size());
    for (std::size_t j = 0; j < rows.size(); ++j) {
        const Json& row = rows[j];
        const std::string where = "heights" + indexPath(j);
        if (!row.is_array())
            return s.fail(where, "expected a row of heights, got " + brief(row));
        if (row.size() != grid.columns)
            return s.fail(where, "has " + std::to_string(row.size()) + " heights and row 0 has " +
                                     std::to_string(grid.columns) +
                                     " (every row needs the same count)");
        for (std::size_t i = 0; i < row.size(); ++i) {
            const Json& h = row[i];
            const double v = h.is_number() ? h.get<double>() : std::nan("");
            if (!h.is_number() || !std::isfinite(v) || std::abs(v) > kMaxLength)
                return s.fail(where + indexPath(i),
                              "expected a finite height within " + lengthText(kMaxLength) +
                                  " m, got " + brief(h));
            grid.heights.push_back(float(v));
        }
    }
    return {};
}

Status readHeightsPng(const ObjectReader& s, const std::string& baseDir, HeightFieldDesc& grid) {
    RUBBLE_TRY(s.read("file", grid.file));
    grid.file = (std::filesystem::path(baseDir) / grid.file).lexically_normal().string();
    float scale = 1.0f;
    RUBBLE_TRY(s.require("height_scale"));
    RUBBLE_TRY(s.read("height_scale", scale, Range::Length));
    int width = 0, height = 0, channels = 0;
    if (!stbi_info(grid.file.c_str(), &width, &height, &channels))
        return s.fail("file", grid.file + ": not a readable PNG (" +
                                  std::string(stbi_failure_reason()) + ")");
    if (channels != 1 || !stbi_is_16_bit(grid.file.c_str()))
        return s.fail("file", grid.file + ": a height field PNG must be 16-bit greyscale, and " +
                                  "this one has " + std::to_string(channels) + " channel(s) of " +
                                  (stbi_is_16_bit(grid.file.c_str()) ? "16" : "8") + " bits");
    if (std::size_t(width) * std::size_t(height) > kMaxMeshVertices)
        return s.fail("file", grid.file + ": " + std::to_string(width) + " x " +
                                  std::to_string(height) + " samples, more than the " +
                                  std::to_string(kMaxMeshVertices) + " rubble takes");
    stbi_us* pixels = stbi_load_16(grid.file.c_str(), &width, &height, &channels, 1);
    if (!pixels)
        return s.fail("file", grid.file + ": " + std::string(stbi_failure_reason()));
    // Image rows run along z, columns along x.
    grid.rows = std::uint32_t(height);
    grid.columns = std::uint32_t(width);
    grid.heights.resize(std::size_t(width) * std::size_t(height));
    for (std::size_t k = 0; k < grid.heights.size(); ++k)
        grid.heights[k] = float(pixels[k]) / kPngWhite * scale;
    stbi_image_free(pixels);
    return {};
}

} // namespace

Status readHeightField(const ObjectReader& s, const std::string& baseDir, ShapeDesc& d) {
    HeightFieldDesc grid;
    if (s.has("heights") == s.has("file"))
        return makeError(ErrorKind::BadInput, s.where(),
                         "a heightfield gives \"heights\" or \"file\" (a 16-bit greyscale PNG), "
                         "one of them");
    if (s.has("heights")) {
        if (s.has("height_scale"))
            return s.fail("height_scale", "goes with \"file\" (a PNG); \"heights\" are metres");
        RUBBLE_TRY(readHeightsArray(s, grid));
    } else {
        RUBBLE_TRY(readHeightsPng(s, baseDir, grid));
    }
    if (grid.rows < 2 || grid.columns < 2)
        return s.fail(s.has("heights") ? "heights" : "file",
                      "needs at least 2 x 2 heights, got " + std::to_string(grid.rows) + " rows of " +
                          std::to_string(grid.columns));
    if (std::size_t(grid.rows) * grid.columns > kMaxMeshVertices)
        return s.fail("heights", std::to_string(grid.rows) + " x " + std::to_string(grid.columns) +
                                     " heights, more than the " +
                                     std::to_string(kMaxMeshVertices) + " rubble takes");
    RUBBLE_TRY(s.require("spacing"));
    const Json& spacing = s.at("spacing");
    if (!spacing.is_array() || spacing.size() != 2)
        return s.fail("spacing", "expected [dx, dz], got " + brief(spacing));
    for (int k = 0; k < 2; ++k) {
        const double v = spacing[k].is_number() ? spacing[k].get<double>() : -1.0;
        if (!(std::isfinite(v) && v >= kMinLength && v <= kMaxLength))
            return s.fail("spacing", "expected two spacings from " + lengthText(kMinLength) +
                                         " to " + lengthText(kMaxLength) + " m, got " +
                                         brief(spacing));
        grid.spacing[k] = float(v);
    }
    const glm::vec2 size = grid.spacing * glm::vec2(grid.columns - 1, grid.rows - 1);
    if (size.x > float(kMaxLength) || size.y > float(kMaxLength))
        return s.fail("spacing", "the grid spans more than " + lengthText(kMaxLength) + " m");
    d.type = ShapeType::Mesh;
    heightFieldTriangles(grid, d.points, d.triangles);
    d.file = grid.file;
    d.heightField = std::move(grid);
    return {};
}

void heightFieldTriangles(const HeightFieldDesc& grid, std::vector<glm::vec3>& points,
                          std::vector<glm::uvec3>& triangles) {
    const std::uint32_t nx = grid.columns, nz = grid.rows;
    const float x0 = -0.5f * grid.spacing.x * float(nx - 1);
    const float z0 = -0.5f * grid.spacing.y * float(nz - 1);
    points.clear();
    triangles.clear();
    for (std::uint32_t j = 0; j < nz; ++j)
        for (std::uint32_t i = 0; i < nx; ++i)
            points.emplace_back(x0 + grid.spacing.x * float(i), grid.heights[j * nx + i],
                                z0 + grid.spacing.y * float(j));
    // Cell (i, j): corners a (i, j), b (i + 1, j), c (i, j + 1), d (i + 1, j + 1); (a, c, b) and
    // (b, c, d) face +y.
    for (std::uint32_t j = 0; j + 1 < nz; ++j)
        for (std::uint32_t i = 0; i + 1 < nx; ++i) {
            const std::uint32_t a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
            triangles.emplace_back(a, c, b);
            triangles.emplace_back(b, c, d);
        }
}

} // namespace rubble
