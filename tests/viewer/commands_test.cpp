// tests/viewer/commands_test.cpp: `rubble render` and `rubble view` as a user runs them: files
// written, pictures checked by pixels, bad options refused with exit status 2, and the viewer
// opened, run for 60 frames and closed under Xvfb.
#include <unistd.h>

#include <gtest/gtest.h>

#include "host/viewer/camera.h"
#include "host/viewer/scene_view.h"
#include "host/viewer/xvfb_server.h"
#include "support/test_util.h"
#include "viewer_test_util.h"

namespace rubble {
namespace {

constexpr int kWidth = 320, kHeight = 180;
const char* kCamera = "0,3,10,0,2.2,0";
const glm::vec3 kEye{0, 3, 10}, kTarget{0, 2.2f, 0};

// Body 1 rests still (static), body 2 falls from high up.
const char* kScene = R"({"format": "rubble-scene", "version": 1, "name": "cmd",
  "simulation": {"dt": 0.01, "steps": 100},
  "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.6, 0.6, 0.6]}},
  "bodies": [{"name": "floor", "shape": "floor", "static": true},
             {"name": "still", "shape": "crate", "static": true, "position": [-1.5, 0.6, 0]},
             {"name": "faller", "shape": "crate", "mass": 1, "position": [1.5, 4, 0]}]})";

struct Fixture {
    std::string dir, scene;
};

Fixture makeScene(const std::string& name) {
    Fixture f{test::tempDir(name), ""};
    f.scene = f.dir + "/scene.json";
    test::writeText(f.scene, kScene);
    return f;
}

glm::ivec2 pixelOf(glm::vec3 world) {
    const glm::vec3 p =
        viewer::projectToPixel(viewer::Camera::lookingAt(kEye, kTarget), world, kWidth, kHeight);
    EXPECT_TRUE(p.x >= 0 && p.x < kWidth && p.y >= 0 && p.y < kHeight) << "off screen";
    return {std::clamp(int(p.x), 0, kWidth - 1), std::clamp(int(p.y), 0, kHeight - 1)};
}

// A render that could not make a context skips outside CI, and fails in it.
#define SKIP_WITHOUT_GL(result)                                                                    \
    do {                                                                                           \
        if ((result).exitCode == 1 &&                                                              \
            (result).output.find("no OpenGL 3.3 context") != std::string::npos) {                  \
            if (test::inCi()) FAIL() << "CI is set and no OpenGL context: " << (result).output;    \
            GTEST_SKIP() << (result).output;                                                       \
        }                                                                                          \
    } while (0)

viewer::Image readImage(const std::string& path) {
    Result<viewer::Image> image = viewer::readPng(path);
    EXPECT_TRUE(image.ok()) << (image.ok() ? "" : image.error().describe());
    return image.ok() ? std::move(*image) : viewer::Image{};
}

TEST(RenderCommand, WritesAPngWithTheBodiesWhereTheCameraSays) {
    const Fixture f = makeScene("render_png");
    const test::CommandResult r =
        test::runRubble("render " + f.scene + " --out " + f.dir + "/a.png --size 320x180 " +
                        "--samples 1 --camera " + kCamera);
    SKIP_WITHOUT_GL(r);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("cmd: 1 frame 320x180, wrote " + f.dir + "/a.png"), std::string::npos)
        << r.output;
    const viewer::Image image = readImage(f.dir + "/a.png");
    ASSERT_EQ(image.width, kWidth);
    ASSERT_EQ(image.height, kHeight);
    for (std::uint32_t body : {1u, 2u}) {
        const glm::vec3 position = body == 1 ? glm::vec3(-1.5f, 0.6f, 0) : glm::vec3(1.5f, 4, 0);
        const glm::ivec2 p = pixelOf(position);
        EXPECT_TRUE(test::looksLike(image, p.x, p.y, viewer::bodyColour(body)))
            << "body " << body << ": " << test::describePixel(image, p.x, p.y);
    }
    EXPECT_GT(test::distinctColours(image), 50u);
}

TEST(RenderCommand, WritesNumberedFramesThatShowTheFall) {
    const Fixture f = makeScene("render_dir");
    const test::CommandResult r =
        test::runRubble("render " + f.scene + " --out " + f.dir + "/frames/ --frames 3 " +
                        "--every 30 --size 320x180 --samples 1 --camera " + kCamera);
    SKIP_WITHOUT_GL(r);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const viewer::Image first = readImage(f.dir + "/frames/frame_00000.png");
    const viewer::Image last = readImage(f.dir + "/frames/frame_00002.png");
    EXPECT_FALSE(std::ifstream(f.dir + "/frames/frame_00003.png").good());
    ASSERT_EQ(first.rgb.size(), last.rgb.size());
    // After 60 steps of 0.01 s the faller is 1.77 m lower: gone from where it was.
    const glm::ivec2 start = pixelOf({1.5f, 4.0f, 0.0f});
    const glm::ivec2 end = pixelOf({1.5f, 4.0f - 0.5f * 9.81f * 0.36f, 0.0f});
    EXPECT_TRUE(test::looksLike(first, start.x, start.y, viewer::bodyColour(2)));
    EXPECT_FALSE(test::looksLike(last, start.x, start.y, viewer::bodyColour(2)))
        << test::describePixel(last, start.x, start.y);
    EXPECT_TRUE(test::looksLike(last, end.x, end.y, viewer::bodyColour(2)))
        << test::describePixel(last, end.x, end.y);
    // The still body has not moved.
    const glm::ivec2 still = pixelOf({-1.5f, 0.6f, 0.0f});
    EXPECT_EQ(first.at(still.x, still.y), last.at(still.x, still.y));
}

TEST(RenderCommand, ReplaysARecordedRun) {
    const Fixture f = makeScene("render_replay");
    const test::CommandResult run = test::runRubble(
        "run " + f.scene + " --steps 60 --every 20 --out " + f.dir + "/t.jsonl --quiet");
    ASSERT_EQ(run.exitCode, 0) << run.output;
    const test::CommandResult r =
        test::runRubble("render " + f.scene + " --replay " + f.dir + "/t.jsonl --start 60 --out " +
                        f.dir + "/r.png --size 320x180 --samples 1 --camera " + kCamera);
    SKIP_WITHOUT_GL(r);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const viewer::Image image = readImage(f.dir + "/r.png");
    const glm::ivec2 end = pixelOf({1.5f, 4.0f - 0.5f * 9.81f * 0.36f, 0.0f});
    EXPECT_TRUE(test::looksLike(image, end.x, end.y, viewer::bodyColour(2)))
        << test::describePixel(image, end.x, end.y);
}

TEST(RenderCommand, RefusesBadInputWithStatus2) {
    const Fixture f = makeScene("render_bad");
    test::writeText(f.dir + "/bad.csv", "step,time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"
                                        "0,0,faller,1,2\n");
    const struct {
        std::string args, expected;
    } cases[] = {
        {"--out " + f.dir + "/a.png --size 10x10", "--size"},
        {"--out " + f.dir + "/a.png --size wide", "--size"},
        {"--out " + f.dir + "/a.png --camera 1,2,3", "--camera"},
        {"--out " + f.dir + "/a.png --camera 1,2,3,4,5,x", "--camera"},
        {"--out " + f.dir + "/a.png --frames 3", "a .png file holds one frame"},
        {"--out " + f.dir + "/a.gif", "expected FILE.png, a folder DIR/, or a video"},
        {"--out " + f.dir + "/a.png --gl metal", "--gl"},
        {"--out " + f.dir + "/a.png --every 0", "--every"},
        {"--out " + f.dir + "/a.png --replay " + f.dir + "/bad.csv", f.dir + "/bad.csv:2:"},
        {"--out " + f.dir + "/a.png --replay " + f.dir + "/none.csv", f.dir + "/none.csv"},
    };
    for (const auto& c : cases) {
        const test::CommandResult r = test::runRubble("render " + f.scene + " " + c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    }
    const test::CommandResult missing =
        test::runRubble("render " + f.dir + "/nope.json --out x.png");
    EXPECT_EQ(missing.exitCode, 2) << missing.output;
    EXPECT_NE(missing.output.find("nope.json"), std::string::npos) << missing.output;
}

TEST(RenderCommand, VideoWithoutFfmpegSaysSoWithStatus2) {
    const Fixture f = makeScene("render_noffmpeg");
    const test::CommandResult r =
        test::runShell("env PATH=/nonexistent " + std::string(RUBBLE_BINARY) + " render " +
                       f.scene + " --out " + f.dir + "/v.mp4 --frames 3");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("video needs ffmpeg, which is not installed"), std::string::npos)
        << r.output;
    EXPECT_FALSE(std::ifstream(f.dir + "/v.mp4").good());
}

TEST(RenderCommand, VideoThroughFfmpeg) {
    if (viewer::findOnPath("ffmpeg").empty()) {
        if (test::inCi()) FAIL() << "CI is set and ffmpeg is not installed (scripts/setup.sh)";
        GTEST_SKIP() << "ffmpeg is not installed (optional)";
    }
    const Fixture f = makeScene("render_video");
    const test::CommandResult r =
        test::runRubble("render " + f.scene + " --out " + f.dir + "/v.mp4 --frames 10 " +
                        "--every 3 --size 160x90 --samples 1");
    SKIP_WITHOUT_GL(r);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_GT(test::readText(f.dir + "/v.mp4").size(), 1000u);
}

// `rubble view` needs a display: the test's own when it has one, else one from xvfb-run.
std::string displayPrefix() {
    const char* display = std::getenv("DISPLAY");
    if (display && *display) return "";
    if (viewer::findOnPath("xvfb-run").empty()) return "none";
    return "xvfb-run -a -s '-screen 0 1024x768x24' ";
}

TEST(ViewCommand, OpensRunsSixtyFramesAndQuitsUnderXvfb) {
    const std::string prefix = displayPrefix();
    if (prefix == "none") {
        if (test::inCi()) FAIL() << "CI is set, DISPLAY is unset and xvfb-run is not installed";
        GTEST_SKIP() << "no DISPLAY and no xvfb-run";
    }
    const Fixture f = makeScene("view_xvfb");
    const test::CommandResult r =
        test::runShell(prefix + RUBBLE_BINARY + " view " + f.scene + " --frames 60 --screenshot " +
                       f.dir + "/shot.png --size 320x180 --camera " + kCamera);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const viewer::Image image = readImage(f.dir + "/shot.png");
    ASSERT_EQ(image.width, kWidth);
    ASSERT_EQ(image.height, kHeight);
    const glm::ivec2 still = pixelOf({-1.5f, 0.6f, 0.0f});
    EXPECT_TRUE(test::looksLike(image, still.x, still.y, viewer::bodyColour(1)))
        << test::describePixel(image, still.x, still.y);
    // 60 frames are 60 steps: the faller is 1.77 m lower.
    const glm::ivec2 fallen = pixelOf({1.5f, 4.0f - 0.5f * 9.81f * 0.36f, 0.0f});
    EXPECT_TRUE(test::looksLike(image, fallen.x, fallen.y, viewer::bodyColour(2)))
        << test::describePixel(image, fallen.x, fallen.y);
    EXPECT_GT(test::distinctColours(image), 50u);
}

TEST(ViewCommand, WithoutADisplaySaysWhatToDo) {
    const Fixture f = makeScene("view_nodisplay");
    const test::CommandResult r = test::runShell("env -u DISPLAY -u WAYLAND_DISPLAY " +
                                                 std::string(RUBBLE_BINARY) + " view " + f.scene);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("xvfb-run"), std::string::npos) << r.output;
}

} // namespace
} // namespace rubble
