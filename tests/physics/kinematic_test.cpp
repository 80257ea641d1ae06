// tests/physics/kinematic_test.cpp: kinematic bodies on the CPU pipeline: moved by their
// velocities or a target pose, infinite mass in the solve, carrying and pushing dynamic bodies,
// waking and keeping awake what they touch.
#include <gtest/gtest.h>

#include "support/test_util.h"

namespace rubble {
namespace {

// A 4 x 4 m platform, 0.2 m thick, moving along x at `speed`, with a crate resting on it that
// starts at the platform's speed; optionally a second crate on the platform at rest.
std::string platformScene(float speed, const std::string& crateVelocity) {
    const std::string v = std::to_string(speed);
    return R"({"format": "rubble-scene", "version": 1, "simulation": {"dt": 0.016666667},
      "materials": {"default": {"friction": 0.6}},
      "shapes": {"deck": {"type": "box", "half_extents": [2, 0.1, 2]},
                 "crate": {"type": "box", "half_extents": [0.25, 0.25, 0.25]}},
      "bodies": [{"name": "platform", "shape": "deck", "kinematic": true,
                  "position": [0, 1, 0], "linear_velocity": [)" + v + R"(, 0, 0]},
                 {"name": "crate", "shape": "crate", "mass": 2, "position": [-1, 1.35, 0.3],
                  "linear_velocity": )" + crateVelocity + "}]}";
}

TEST(Kinematic, PlatformCarriesABoxWithoutSlip) {
    World w = test::worldFromText(platformScene(1.0f, "[1, 0, 0]"));
    const std::uint32_t platform = *w.findBody("platform"), crate = *w.findBody("crate");
    // Let the crate settle on the deck, then measure over 2 s.
    ASSERT_TRUE(test::stepWorld(w, 30));
    const glm::vec3 p0 = w.body(platform).position, c0 = w.body(crate).position;
    ASSERT_TRUE(test::stepWorld(w, 120));
    const glm::vec3 p1 = w.body(platform).position, c1 = w.body(crate).position;
    // The platform moves by its velocity alone: 2 m along x, nothing else.
    EXPECT_NEAR(p1.x - p0.x, 2.0f, 1e-3f);
    EXPECT_EQ(p1.y, p0.y);
    EXPECT_EQ(p1.z, p0.z);
    const glm::vec3 slip = (c1 - c0) - (p1 - p0);
    EXPECT_LT(glm::length(slip), 1e-3f) << "slip " << slip.x << ", " << slip.y << ", " << slip.z;
    EXPECT_NEAR(w.body(crate).linearVelocity.x, 1.0f, 1e-3f);
    EXPECT_GT(c1.y, 1.35f - 0.01f) << "the crate sank into the platform";
    EXPECT_TRUE(w.body(platform).isKinematic);
    EXPECT_EQ(w.body(platform).mass, 0.0f);
}

TEST(Kinematic, BoxAtRestCatchesUpThenRidesAlong) {
    // Friction 0.6 brings the crate to 1 m/s in 1 / (0.6 g) = 0.17 s.
    World w = test::worldFromText(platformScene(1.0f, "[0, 0, 0]"));
    const std::uint32_t platform = *w.findBody("platform"), crate = *w.findBody("crate");
    ASSERT_TRUE(test::stepWorld(w, 60));
    EXPECT_NEAR(w.body(crate).linearVelocity.x, 1.0f, 1e-3f);
    const float gap0 = w.body(crate).position.x - w.body(platform).position.x;
    ASSERT_TRUE(test::stepWorld(w, 60));
    const float gap1 = w.body(crate).position.x - w.body(platform).position.x;
    EXPECT_LT(std::abs(gap1 - gap0), 1e-3f);
}

TEST(Kinematic, SlowPlatformKeepsWhatItCarriesAwake) {
    // 1 cm/s is under the sleep speed: without the platform's motion the crate would sleep in
    // 0.5 s and stay behind.
    World w = test::worldFromText(platformScene(0.01f, "[0.01, 0, 0]"));
    const std::uint32_t platform = *w.findBody("platform"), crate = *w.findBody("crate");
    ASSERT_TRUE(test::stepWorld(w, 30));
    const glm::vec3 p0 = w.body(platform).position, c0 = w.body(crate).position;
    ASSERT_TRUE(test::stepWorld(w, 180));
    EXPECT_FALSE(w.body(crate).asleep);
    EXPECT_FALSE(w.body(platform).asleep);
    const glm::vec3 slip = (w.body(crate).position - c0) - (w.body(platform).position - p0);
    EXPECT_LT(glm::length(slip), 1e-3f);
    EXPECT_NEAR(w.body(platform).position.x - p0.x, 0.03f, 1e-4f);
}

TEST(Kinematic, PusherWakesAndPushesABox) {
    // The crate sleeps on the floor before the pusher, 1 m away at 1 m/s, reaches it.
    World w = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "materials": {"default": {"friction": 0.4}},
      "shapes": {"ground": {"type": "plane"},
                 "blade": {"type": "box", "half_extents": [0.1, 0.4, 1]},
                 "crate": {"type": "box", "half_extents": [0.25, 0.25, 0.25]}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true},
                 {"name": "pusher", "shape": "blade", "kinematic": true,
                  "position": [-1.35, 0.41, 0], "linear_velocity": [1, 0, 0]},
                 {"name": "crate", "shape": "crate", "mass": 5, "position": [0, 0.25, 0]}]})");
    const std::uint32_t pusher = *w.findBody("pusher"), crate = *w.findBody("crate");
    ASSERT_TRUE(test::stepWorld(w, 54)); // 0.9 s: 0.1 m before the touch
    EXPECT_TRUE(w.body(crate).asleep);
    EXPECT_NEAR(w.body(crate).position.x, 0.0f, 1e-4f);
    ASSERT_TRUE(test::stepWorld(w, 126)); // to 3 s: pushed for 2 s
    const BodyState p = w.body(pusher), c = w.body(crate);
    // The pusher kept its course: contacts do not move it.
    EXPECT_NEAR(p.position.x, -1.35f + 3.0f, 2e-3f);
    EXPECT_NEAR(p.position.y, 0.41f, 1e-6f);
    // The crate is in front of the blade, touching it, moving with it.
    EXPECT_FALSE(c.asleep);
    EXPECT_NEAR(c.position.x - p.position.x, 0.35f, 0.02f);
    EXPECT_NEAR(c.linearVelocity.x, 1.0f, 0.05f);
    EXPECT_NEAR(c.position.y, 0.25f, 0.01f);
}

TEST(Kinematic, TargetPoseIsReachedEachStep) {
    World w = test::worldFromText(platformScene(0.0f, "[0, 0, 0]"));
    const std::uint32_t platform = *w.findBody("platform"), crate = *w.findBody("crate");
    ASSERT_TRUE(test::stepWorld(w, 30));
    const float dt = w.options().dt;
    // The crate's place in the platform's frame.
    auto onDeck = [&] {
        const BodyState p = w.body(platform);
        return glm::conjugate(p.orientation) * (w.body(crate).position - p.position);
    };
    glm::vec3 settled(0.0f);
    // Slide 0.5 m along z over 1 s, turning 0.2 rad about y.
    for (int i = 1; i <= 60; ++i) {
        const float t = float(i) / 60.0f;
        const glm::vec3 target(0.0f, 1.0f, 0.5f * t);
        const glm::quat turn = glm::angleAxis(0.2f * t, glm::vec3(0, 1, 0));
        const glm::vec3 before = w.body(platform).position;
        ASSERT_TRUE(w.setKinematicTarget(platform, target, turn).ok());
        EXPECT_NEAR(w.body(platform).linearVelocity.z, (target.z - before.z) / dt, 1e-3f);
        EXPECT_NEAR(w.body(platform).angularVelocity.y, 0.2f, 1e-3f);
        ASSERT_TRUE(w.step().ok());
        EXPECT_EQ(w.body(platform).position, target);
        const glm::quat q = w.body(platform).orientation;
        EXPECT_LT(glm::length(glm::vec4(q.w - turn.w, q.x - turn.x, q.y - turn.y, q.z - turn.z)),
                  1e-6f);
        // The start is a jolt to 0.5 m/s that friction takes 0.1 s to follow.
        if (i == 15) settled = onDeck();
    }
    // Then the crate rides along, turning with the deck: its place on the deck stays.
    EXPECT_LT(glm::length(onDeck() - settled), 2e-3f);
    // Its velocity is the deck's at its place: v + omega x r.
    const glm::vec3 arm = w.body(crate).position - w.body(platform).position;
    const glm::vec3 carried = glm::vec3(0.0f, 0.0f, 0.5f) + glm::cross(glm::vec3(0, 0.2f, 0), arm);
    EXPECT_LT(glm::length(w.body(crate).linearVelocity - carried), 0.01f);
    // Errors: a body that is not kinematic, a non-finite pose.
    EXPECT_FALSE(w.setKinematicTarget(crate, glm::vec3(0.0f), glm::quat(1, 0, 0, 0)).ok());
    EXPECT_FALSE(
        w.setKinematicTarget(platform, glm::vec3(NAN, 0.0f, 0.0f), glm::quat(1, 0, 0, 0)).ok());
}

TEST(Kinematic, ParticlesAndOtherSolversAreRefusedNamingTheBody) {
    for (const char* simulation :
         {R"("backend": "opencl", "collision": {"method": "particles"})",
          R"("collision": {"method": "particles"})", R"("solver": {"type": "jacobi"})"}) {
        const Error e = test::sceneError(
            std::string(R"({"format": "rubble-scene", "version": 1, "simulation": {)") +
            simulation + R"(},
              "shapes": {"b": {"type": "box", "half_extents": [1, 1, 1]}},
              "bodies": [{"name": "lift", "shape": "b", "kinematic": true}]})");
        EXPECT_EQ(e.kind, ErrorKind::NotSupported) << e.describe();
        EXPECT_NE(e.where.find("bodies[0].kinematic"), std::string::npos) << e.describe();
        EXPECT_NE(e.message.find("\"lift\""), std::string::npos) << e.describe();
    }
}

} // namespace
} // namespace rubble
