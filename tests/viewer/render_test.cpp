// tests/viewer/render_test.cpp: frames of known scenes drawn off-screen and checked by pixels:
// bodies and ground where the camera math puts them, nothing blank, motion where bodies moved.
#include <gtest/gtest.h>

#include "host/viewer/offscreen_context.h"
#include "host/viewer/render_target.h"
#include "host/viewer/renderer.h"
#include "host/viewer/scene_view.h"
#include "support/test_util.h"
#include "viewer_test_util.h"

namespace rubble {
namespace {

constexpr int kWidth = 320, kHeight = 180;

// A floor, a box and a sphere resting apart, and a box high up that falls (no contact with
// anything in the first second).
const char* kScene = R"({"format": "rubble-scene", "version": 1, "name": "pixels",
  "simulation": {"dt": 0.01},
  "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
             "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
             "ball": {"type": "sphere", "radius": 0.5}},
  "bodies": [{"name": "floor", "shape": "floor", "static": true},
             {"name": "box", "shape": "crate", "static": true, "position": [-1.2, 0.5, 0]},
             {"name": "ball", "shape": "ball", "static": true, "position": [1.2, 0.5, 0]},
             {"name": "faller", "shape": "crate", "mass": 1, "position": [0, 4, -2]}]})";

const glm::vec3 kRed{1.0f, 0.05f, 0.05f}, kGreen{0.05f, 1.0f, 0.05f}, kBlue{0.05f, 0.1f, 1.0f};

class Render : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        Result<viewer::OffscreenContext> c = viewer::OffscreenContext::create();
        if (c)
            context_ = new viewer::OffscreenContext(std::move(*c));
        else
            failure_ = c.error().describe();
    }
    static void TearDownTestSuite() {
        delete context_;
        context_ = nullptr;
    }

    void SetUp() override {
        if (!context_) {
            if (test::inCi()) FAIL() << "CI is set and no OpenGL context can be made: " << failure_;
            GTEST_SKIP() << "no OpenGL context: " << failure_;
        }
        world_.emplace(test::worldFromText(kScene));
        view_.emplace(*world_);
        view_->setBodyColour(1, kRed);
        view_->setBodyColour(2, kGreen);
        view_->setBodyColour(3, kBlue);
        Result<viewer::Renderer> r = viewer::Renderer::create(world_->shapes());
        ASSERT_TRUE(r.ok()) << r.error().describe();
        renderer_.emplace(std::move(*r));
        Result<viewer::RenderTarget> t = viewer::RenderTarget::create(kWidth, kHeight, 1);
        ASSERT_TRUE(t.ok()) << t.error().describe();
        target_.emplace(std::move(*t));
    }

    void TearDown() override {
        target_.reset();
        renderer_.reset();
    }

    viewer::Image render() {
        viewer::DrawList frame;
        std::vector<shared::BodyPose> poses;
        viewer::currentPoses(*world_, poses);
        view_->build(poses, &*world_, viewer::Overlays{}, frame);
        target_->bind();
        renderer_->draw(frame, camera_, kWidth, kHeight);
        return target_->read();
    }

    glm::ivec2 pixelOf(glm::vec3 world) const {
        const glm::vec3 p = viewer::projectToPixel(camera_, world, kWidth, kHeight);
        return {int(p.x), int(p.y)};
    }

    glm::vec3 positionOf(std::uint32_t body) const { return world_->body(body).position; }

    static viewer::OffscreenContext* context_;
    static std::string failure_;
    std::optional<World> world_;
    std::optional<viewer::SceneView> view_;
    std::optional<viewer::Renderer> renderer_;
    std::optional<viewer::RenderTarget> target_;
    viewer::Camera camera_ = viewer::Camera::lookingAt({0.0f, 3.0f, 7.0f}, {0.0f, 1.0f, 0.0f});
};

viewer::OffscreenContext* Render::context_ = nullptr;
std::string Render::failure_;

TEST_F(Render, BodiesAppearWhereTheCameraPutsThem) {
    const viewer::Image image = render();
    ASSERT_EQ(image.width, kWidth);
    ASSERT_EQ(image.height, kHeight);
    const struct {
        std::uint32_t body;
        glm::vec3 colour;
    } expected[] = {{1, kRed}, {2, kGreen}, {3, kBlue}};
    for (const auto& e : expected) {
        const glm::ivec2 p = pixelOf(positionOf(e.body));
        ASSERT_TRUE(p.x >= 0 && p.x < kWidth && p.y >= 0 && p.y < kHeight) << "off screen";
        EXPECT_TRUE(test::looksLike(image, p.x, p.y, e.colour))
            << world_->bodyName(e.body) << ": " << test::describePixel(image, p.x, p.y);
    }
}

TEST_F(Render, GroundAndBackgroundWhereExpected) {
    const viewer::Image image = render();
    const glm::vec3 background = renderer_->palette().background;
    // The top corner looks over the horizon of a large ground: background.
    const glm::vec3 sky = test::linearPixel(image, kWidth - 2, 1);
    EXPECT_LT(glm::length(sky - background), 0.02f) << test::describePixel(image, kWidth - 2, 1);
    // A point on the floor in front of the bodies shows the grey ground: equal channels, and
    // brighter than the background.
    const glm::ivec2 g = pixelOf({0.5f, 0.0f, 2.5f});
    ASSERT_TRUE(g.y > 0 && g.y < kHeight);
    const glm::vec3 ground = test::linearPixel(image, g.x, g.y);
    EXPECT_TRUE(test::looksLike(image, g.x, g.y, glm::vec3(1.0f), 0.03f))
        << test::describePixel(image, g.x, g.y);
    EXPECT_GT(ground.r + ground.g + ground.b, 3.0f * (background.b + 0.05f));
}

TEST_F(Render, FrameIsNotBlank) {
    const viewer::Image image = render();
    EXPECT_GT(test::distinctColours(image), 50u);
}

TEST_F(Render, FallingBodyMovesInThePicture) {
    const viewer::Image before = render();
    const glm::vec3 start = positionOf(3);
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(world_->step().ok());
    const glm::vec3 end = positionOf(3);
    ASSERT_LT(end.y, start.y - 1.0f); // fell about 1.8 m in 0.6 s
    const viewer::Image after = render();

    const glm::ivec2 a = pixelOf(start), b = pixelOf(end);
    ASSERT_GT(glm::length(glm::vec2(b - a)), 10.0f) << "the fall must move it on screen";
    // Where it was: blue before, not blue after; where it is: blue now.
    EXPECT_TRUE(test::looksLike(before, a.x, a.y, kBlue)) << test::describePixel(before, a.x, a.y);
    EXPECT_FALSE(test::looksLike(after, a.x, a.y, kBlue)) << test::describePixel(after, a.x, a.y);
    EXPECT_TRUE(test::looksLike(after, b.x, b.y, kBlue)) << test::describePixel(after, b.x, b.y);
    // The two frames differ in a region around the body, and only a small part of the picture.
    std::size_t changed = 0;
    for (std::size_t i = 0; i < before.rgb.size(); i += 3)
        changed += (before.rgb[i] != after.rgb[i] || before.rgb[i + 1] != after.rgb[i + 1] ||
                    before.rgb[i + 2] != after.rgb[i + 2]);
    EXPECT_GT(changed, 100u);
    EXPECT_LT(changed, std::size_t(kWidth * kHeight) / 4);
}

TEST_F(Render, ProjectionMatchesTheCameraCentre) {
    // The target lands in the middle of the picture; a point above it, higher up.
    const glm::vec3 centre = viewer::projectToPixel(camera_, camera_.target, kWidth, kHeight);
    EXPECT_NEAR(centre.x, kWidth / 2.0f, 0.01f);
    EXPECT_NEAR(centre.y, kHeight / 2.0f, 0.01f);
    const glm::vec3 above =
        viewer::projectToPixel(camera_, camera_.target + glm::vec3(0, 1, 0), kWidth, kHeight);
    EXPECT_LT(above.y, centre.y);
}

TEST_F(Render, FramingKeepsEveryBodyInView) {
    const viewer::Camera framed =
        viewer::Camera::framing(view_->bounds(), float(kWidth) / float(kHeight));
    for (std::uint32_t i = 1; i < world_->bodyCount(); ++i) {
        const glm::vec3 p = viewer::projectToPixel(framed, positionOf(i), kWidth, kHeight);
        EXPECT_TRUE(p.x > 0 && p.x < kWidth && p.y > 0 && p.y < kHeight && p.z > 0 && p.z < 1)
            << world_->bodyName(i);
    }
}

TEST_F(Render, OverlaysDrawLinesAndText) {
    viewer::Overlays overlays;
    overlays.aabbs = true;
    viewer::DrawList frame;
    std::vector<shared::BodyPose> poses;
    viewer::currentPoses(*world_, poses);
    view_->build(poses, &*world_, overlays, frame);
    EXPECT_EQ(frame.lines.size(), 3u * 24u); // 12 edges of each of the three bodies
    frame.text.push_back(viewer::statusLine(0, 0.0, *world_, "cpu", "cpu"));
    target_->bind();
    renderer_->draw(frame, camera_, kWidth, kHeight);
    const viewer::Image image = target_->read();
    // The text sits in the top-left corner on a dark backdrop: light pixels there.
    int light = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 120; ++x) light += image.at(x, y).r > 200;
    EXPECT_GT(light, 40);
}

} // namespace
} // namespace rubble
