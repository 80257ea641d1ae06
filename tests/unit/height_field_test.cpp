// tests/unit/height_field_test.cpp: heightfield shapes (host/scene/height_field.cpp): the grid's
// triangles, 16-bit greyscale PNGs read to heights, other PNGs refused, and the pipelines that
// refuse level geometry.
#include <array>
#include <cstring>

#include <gtest/gtest.h>

#include "host/scene/height_field.h"
#include "support/test_util.h"

namespace rubble {
namespace {

std::uint32_t crc32(const std::string& bytes) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

void putBig(std::string& out, std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(char((v >> s) & 0xFF));
}

void chunk(std::string& png, const char* type, const std::string& data) {
    putBig(png, std::uint32_t(data.size()));
    const std::string body = std::string(type, 4) + data;
    png += body;
    putBig(png, crc32(body));
}

// A PNG of `width` x `height` samples (channels per pixel, 8 or 16 bits, big-endian), stored
// without compression (deflate's stored blocks).
std::string makePng(int width, int height, int bits, int colourType, int channels,
                    const std::vector<std::uint16_t>& samples) {
    std::string raw;
    for (int y = 0; y < height; ++y) {
        raw.push_back(0); // filter: none
        for (int x = 0; x < width * channels; ++x) {
            const std::uint16_t v = samples[std::size_t(y * width * channels + x)];
            if (bits == 16) raw.push_back(char(v >> 8));
            raw.push_back(char(v & 0xFF));
        }
    }
    std::string z = "\x78\x01";
    z.push_back(1); // final stored block
    const auto len = std::uint16_t(raw.size());
    z.push_back(char(len & 0xFF));
    z.push_back(char(len >> 8));
    z.push_back(char(~len & 0xFF));
    z.push_back(char((~len >> 8) & 0xFF));
    z += raw;
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : raw) a = (a + c) % 65521u, b = (b + a) % 65521u;
    putBig(z, (b << 16) | a);
    std::string png = "\x89PNG\r\n\x1a\n";
    std::string header;
    putBig(header, std::uint32_t(width));
    putBig(header, std::uint32_t(height));
    header += {char(bits), char(colourType), 0, 0, 0};
    chunk(png, "IHDR", header);
    chunk(png, "IDAT", z);
    chunk(png, "IEND", "");
    return png;
}

std::string pngScene(const std::string& png) {
    return R"({"format": "rubble-scene", "version": 1,
      "shapes": {"hill": {"type": "heightfield", "file": ")" + png +
           R"(", "height_scale": 2.0, "spacing": [0.5, 1.0]}},
      "bodies": [{"name": "hill", "shape": "hill", "static": true}]})";
}

TEST(HeightField, TrianglesCoverTheGridFacingUp) {
    HeightFieldDesc grid;
    grid.rows = 3;
    grid.columns = 4;
    grid.spacing = {0.5f, 2.0f};
    for (int k = 0; k < 12; ++k) grid.heights.push_back(0.1f * float(k));
    std::vector<glm::vec3> points;
    std::vector<glm::uvec3> triangles;
    heightFieldTriangles(grid, points, triangles);
    ASSERT_EQ(points.size(), 12u);
    ASSERT_EQ(triangles.size(), 2u * 3u * 2u);
    // Centred in x and z; row j along z, column i along x.
    EXPECT_FLOAT_EQ(points[0].x, -0.75f);
    EXPECT_FLOAT_EQ(points[0].z, -2.0f);
    EXPECT_FLOAT_EQ(points[11].x, 0.75f);
    EXPECT_FLOAT_EQ(points[11].z, 2.0f);
    EXPECT_FLOAT_EQ(points[5].y, 0.5f);
    float area = 0.0f;
    for (const glm::uvec3& t : triangles) {
        const glm::vec3 n = glm::cross(points[t.y] - points[t.x], points[t.z] - points[t.x]);
        EXPECT_GT(n.y, 0.0f);
        area += 0.5f * n.y; // the area projected on y = 0
    }
    EXPECT_NEAR(area, 1.5f * 4.0f, 1e-5f);
}

TEST(HeightField, Reads16BitGreyPngs) {
    const std::string dir = test::tempDir("height_png");
    const std::string png = dir + "/hill.png";
    // 3 columns, 2 rows; white is height_scale metres.
    test::writeText(png, makePng(3, 2, 16, 0, 1, {0, 65535, 32768, 1000, 2000, 3000}));
    Result<Scene> scene = parseScene(pngScene(png), "inline.json", ".");
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    const ShapeDesc& d = scene->shapes[0];
    ASSERT_TRUE(d.heightField.has_value());
    EXPECT_EQ(d.heightField->columns, 3u);
    EXPECT_EQ(d.heightField->rows, 2u);
    EXPECT_FLOAT_EQ(d.heightField->heights[1], 2.0f);
    EXPECT_NEAR(d.heightField->heights[2], 2.0f * 32768.0f / 65535.0f, 1e-6f);
    EXPECT_NEAR(d.heightField->heights[5], 2.0f * 3000.0f / 65535.0f, 1e-6f);
    EXPECT_EQ(d.triangles.size(), 4u);
    const test::CommandResult r = test::runRubble("validate '" + [&] {
        const std::string file = dir + "/scene.json";
        test::writeText(file, pngScene(png));
        return file;
    }() + "'");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("hill (heightfield 3 x 2, 4 triangles)"), std::string::npos)
        << r.output;
}

TEST(HeightField, RefusesPngsThatAreNot16BitGrey) {
    const std::string dir = test::tempDir("height_png_bad");
    const std::vector<std::uint16_t> six{0, 1, 2, 3, 4, 5};
    const std::array<std::pair<const char*, std::string>, 3> cases{{
        {"grey8.png", makePng(3, 2, 8, 0, 1, six)},
        {"rgb16.png", makePng(1, 2, 16, 2, 3, six)},
        {"greyalpha16.png", makePng(3, 1, 16, 4, 2, six)},
    }};
    for (const auto& [name, bytes] : cases) {
        const std::string png = dir + "/" + name;
        test::writeText(png, bytes);
        const std::string file = dir + "/" + std::string(name) + ".json";
        test::writeText(file, pngScene(png));
        const test::CommandResult r = test::runRubble("validate '" + file + "'");
        EXPECT_EQ(r.exitCode, 2) << name << ": " << r.output;
        EXPECT_NE(r.output.find(file + ": shapes.hill.file"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("16-bit greyscale"), std::string::npos) << r.output;
    }
}

TEST(HeightField, DeviceAndParticlesRefuseLevelGeometry) {
    const std::string base = R"({"format": "rubble-scene", "version": 1, "simulation": {SIM},
      "shapes": {"hill": {"type": "heightfield", "spacing": [1, 1], "heights": [[0, 0], [0, 1]]}},
      "bodies": [{"name": "hill", "shape": "hill", "static": true}]})";
    for (const std::string sim : {R"("backend": "opencl")", R"("collision": {"method": "particles"})"}) {
        std::string text = base;
        text.replace(text.find("SIM"), 3, sim);
        const Error e = test::sceneError(text);
        EXPECT_EQ(e.kind, ErrorKind::NotSupported) << e.describe();
        EXPECT_NE(e.describe().find("bodies[0].shape"), std::string::npos) << e.describe();
        EXPECT_NE(e.describe().find("heightfield"), std::string::npos) << e.describe();
    }
}

} // namespace
} // namespace rubble
