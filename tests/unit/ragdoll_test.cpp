// tests/unit/ragdoll_test.cpp: host/scene/ragdoll through the scene loader's `ragdoll`
// generator: parts, names, proportions, joints, scale and bad input.
#include "host/scene/ragdoll.h"

#include <gtest/gtest.h>

#include "support/test_util.h"

namespace rubble {
namespace {

const char* kParts[] = {"chest",     "head",    "upper_arm_l", "upper_arm_r", "forearm_l",
                        "forearm_r", "thigh_l", "thigh_r",     "shin_l",      "shin_r"};

Scene ragdollScene(const std::string& generator) {
    Result<Scene> scene = parseScene(R"({"format": "rubble-scene", "version": 1,
      "materials": {"cloth": {"friction": 0.8}},
      "shapes": {"ground": {"type": "plane"}},
      "bodies": [{"name": "floor", "shape": "ground", "static": true}],
      "generators": [)" + generator + "]}",
                                     "inline.json", ".");
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
    if (!scene.ok()) std::abort();
    return std::move(*scene);
}

// Lowest and highest points of the bodies from index `first` on, y, m.
void verticalExtent(const Scene& s, std::size_t first, float& low, float& high) {
    low = 1e9f;
    high = -1e9f;
    for (std::size_t i = first; i < s.bodies.size(); ++i) {
        const ShapeDesc& shape = s.shapes[s.bodies[i].shape];
        const float h = shape.type == ShapeType::Sphere ? shape.radius : shape.halfExtents.y;
        low = std::min(low, s.bodies[i].position.y - h);
        high = std::max(high, s.bodies[i].position.y + h);
    }
}

TEST(Ragdoll, HasTenNamedPartsAndNineJoints) {
    const Scene s = ragdollScene(
        R"({"type": "ragdoll", "name_prefix": "doll", "position": [1, 3, -2], "material": "cloth"})");
    ASSERT_EQ(s.bodies.size(), 11u);
    for (std::size_t k = 0; k < 10; ++k) {
        EXPECT_EQ(s.bodies[1 + k].name, std::string("doll_") + kParts[k]);
        EXPECT_EQ(s.materials[s.bodies[1 + k].material].name, "cloth");
        EXPECT_FALSE(s.bodies[1 + k].isStatic);
    }
    EXPECT_EQ(s.bodies[1].position, glm::vec3(1, 3, -2)); // the chest's centre
    ASSERT_EQ(s.joints.size(), 9u);
    int balls = 0, hinges = 0;
    for (const JointDesc& j : s.joints) {
        EXPECT_GE(j.a, 1u);
        EXPECT_GE(j.b, 1u);
        const std::string child = s.bodies[j.b].name;
        if (j.type == JointType::Ball) {
            ++balls;
        } else {
            ++hinges;
            // Elbows turn about y, knees about x.
            const glm::vec3 axis = child.find("forearm") != std::string::npos ? glm::vec3(0, 1, 0)
                                                                              : glm::vec3(1, 0, 0);
            EXPECT_EQ(j.axis, axis) << child;
        }
        // The anchor sits between the two parts' centres.
        const glm::vec3 pa = s.bodies[j.a].position, pb = s.bodies[j.b].position;
        EXPECT_LT(glm::length(j.anchor - pa), glm::length(pb - pa)) << child;
        EXPECT_LT(glm::length(j.anchor - pb), glm::length(pb - pa)) << child;
    }
    EXPECT_EQ(balls, 5); // neck, shoulders, hips
    EXPECT_EQ(hinges, 4);
}

TEST(Ragdoll, IsAboutOnePointEightMetresTallAndScales) {
    float low = 0, high = 0;
    verticalExtent(ragdollScene(R"({"type": "ragdoll", "position": [0, 2, 0]})"), 1, low, high);
    EXPECT_NEAR(high - low, 1.8f, 0.05f);
    const Scene big = ragdollScene(R"({"type": "ragdoll", "position": [0, 4, 0], "scale": 2})");
    float bigLow = 0, bigHigh = 0;
    verticalExtent(big, 1, bigLow, bigHigh);
    EXPECT_NEAR(bigHigh - bigLow, 2.0f * (high - low), 1e-4f);
    const Scene unit = ragdollScene(R"({"type": "ragdoll"})");
    EXPECT_EQ(unit.bodies[1].name, "ragdoll0_chest"); // the default prefix names the entry
    float mass = 0, bigMass = 0;
    for (std::size_t i = 1; i < unit.bodies.size(); ++i) {
        mass += *unit.bodies[i].mass;
        bigMass += *big.bodies[i].mass;
    }
    EXPECT_NEAR(mass, 70.0f, 10.0f);
    EXPECT_NEAR(bigMass, 8.0f * mass, 1e-3f);
}

TEST(Ragdoll, TwoRagdollsKeepTheirJointsApart) {
    const Scene s = ragdollScene(R"({"type": "ragdoll", "name_prefix": "a", "position": [0, 2, 0]},
                                    {"type": "ragdoll", "name_prefix": "b", "position": [3, 2, 0]})");
    ASSERT_EQ(s.joints.size(), 18u);
    for (std::size_t k = 9; k < 18; ++k) {
        EXPECT_EQ(s.bodies[s.joints[k].a].name.substr(0, 2), "b_");
        EXPECT_EQ(s.bodies[s.joints[k].b].name.substr(0, 2), "b_");
    }
    World world = test::worldFromText(R"({"format": "rubble-scene", "version": 1,
      "generators": [{"type": "ragdoll", "position": [0, 2, 0], "debris": true}]})");
    EXPECT_EQ(world.bodyCount(), 10u);
}

TEST(Ragdoll, BadFieldsAreNamed) {
    const Error unknown = test::sceneError(R"({"format": "rubble-scene", "version": 1,
      "generators": [{"type": "ragdoll", "sclae": 2}]})");
    EXPECT_EQ(unknown.kind, ErrorKind::BadInput);
    EXPECT_NE(unknown.describe().find("generators[0]"), std::string::npos) << unknown.describe();
    EXPECT_NE(unknown.describe().find("sclae"), std::string::npos) << unknown.describe();
    const Error scale = test::sceneError(R"({"format": "rubble-scene", "version": 1,
      "generators": [{"type": "ragdoll", "scale": 0}]})");
    EXPECT_EQ(scale.kind, ErrorKind::BadInput);
    EXPECT_NE(scale.describe().find("generators[0].scale"), std::string::npos) << scale.describe();
    const Error material = test::sceneError(R"({"format": "rubble-scene", "version": 1,
      "generators": [{"type": "ragdoll", "material": "steel"}]})");
    EXPECT_NE(material.describe().find("generators[0].material"), std::string::npos);
    const Error clash = test::sceneError(R"({"format": "rubble-scene", "version": 1,
      "generators": [{"type": "ragdoll", "name_prefix": "x"}, {"type": "ragdoll", "name_prefix": "x"}]})");
    EXPECT_NE(clash.describe().find("duplicate body name"), std::string::npos) << clash.describe();
}

TEST(Ragdoll, BuilderUsesTheSpec) {
    RagdollSpec spec;
    spec.prefix = "p";
    spec.position = {0, 1, 0};
    spec.scale = 0.5f;
    spec.debris = true;
    const RagdollParts parts = buildRagdoll(spec);
    ASSERT_EQ(parts.shapes.size(), 10u);
    ASSERT_EQ(parts.bodies.size(), 10u);
    ASSERT_EQ(parts.joints.size(), 9u);
    for (std::size_t k = 0; k < 10; ++k) {
        EXPECT_EQ(parts.bodies[k].shape, k);
        EXPECT_TRUE(parts.bodies[k].debris);
    }
    EXPECT_EQ(parts.shapes[1].type, ShapeType::Box);
}

} // namespace
} // namespace rubble
