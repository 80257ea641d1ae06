// tests/gpu/level_mesh_device_test.cpp: static triangle meshes and height fields on the device's
// SAT + PGS path against the CPU reference (tests/physics/level_mesh_test.cpp): a crate landing
// and resting on a flat mesh and on a height field step by step, a box sliding over many
// triangles without bumps (the fast crates at a thin mesh wall: tunnelling_device_test.cpp).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "gpu_fixture.h"
#include "support/level_cases.h"

namespace rubble {
namespace {

class DeviceLevelMesh : public test::GpuTest {
  protected:
    /// The scene of `json` on the device (SAT, PGS) and on the CPU.
    World device(const std::string& json) { return deviceWorld(json); }
    static World cpu(const std::string& json) { return test::worldFromText(json); }

    /// Steps both worlds `steps` times; the body named `name` stays within `tolerance` (m) of
    /// the CPU's position at every step. Returns the largest difference.
    static float stepTwins(World& d, World& c, const std::string& name, int steps,
                           float tolerance) {
        const std::uint32_t body = *c.findBody(name);
        float worst = 0.0f;
        for (int i = 0; i < steps; ++i) {
            EXPECT_TRUE(test::stepWorld(d, 1)) << "device, step " << i;
            EXPECT_TRUE(test::stepWorld(c, 1)) << "cpu, step " << i;
            const float gap = glm::length(d.body(body).position - c.body(body).position);
            worst = std::max(worst, gap);
            if (gap > tolerance) {
                ADD_FAILURE() << name << " is " << gap << " m from the CPU's at step " << i;
                break;
            }
        }
        return worst;
    }
};


std::string flatMeshFile(int n, float cell) {
    const std::string path =
        test::tempDir("level_mesh_device") + "/floor_" + std::to_string(n) + ".obj";
    test::writeText(path, test::flatGridObj(n, cell));
    return path;
}

// One crate over a floor (`floor` a shape's JSON), friction `friction`.
std::string crateOn(const std::string& floor, float friction, const std::string& crateAt) {
    return R"({"format": "rubble-scene", "version": 1,
        "simulation": {"collision": {"method": "sat"}},
        "materials": {"default": {"friction": )" +
           std::to_string(friction) + R"(}},
        "shapes": {"floor": )" +
           floor + R"(,
                   "crate": {"type": "box", "half_extents": [0.5, 0.25, 0.4]}},
        "bodies": [{"name": "floor", "shape": "floor", "static": true},
                   {"name": "crate", "shape": "crate", "mass": 2, )" +
           crateAt + "}]}";
}

std::string meshShape(const std::string& path) {
    return R"({"type": "mesh", "file": ")" + path + R"("})";
}

// Dropped tilted from 0.4 m onto a flat mesh of 0.5 m quads: it lands on a corner, tips onto
// a face over the seams and rests, on the device as on the CPU at every step.
TEST_F(DeviceLevelMesh, CrateLandsAndRestsOnAFlatMeshAsOnTheCpu) {
    const std::string scene =
        crateOn(meshShape(flatMeshFile(20, 0.5f)), 0.5f,
                R"("position": [0.13, 0.7, 0.07], "orientation": [0.98, 0.12, 0.05, 0.15])");
    World d = device(scene), c = cpu(scene);
    const float worst = stepTwins(d, c, "crate", 240, 2e-3f);
    RecordProperty("worst_gap_m", std::to_string(worst));
    const std::uint32_t crate = *d.findBody("crate");
    EXPECT_NEAR(d.body(crate).position.y, 0.25f, 0.01f);
    EXPECT_LT(glm::length(d.body(crate).linearVelocity), 1e-3f);
    EXPECT_GT((d.body(crate).orientation * glm::vec3(0, 1, 0)).y, 0.9999f);
    EXPECT_LT(d.lastStep().largestPenetration, 0.01f);
}

// A 9 x 9 height field of 0.5 m cells whose height is amp exp(-k r^2), as JSON.
std::string fieldShape(float amp, float k, float cx) {
    std::ostringstream heights;
    heights << "[";
    for (int j = 0; j <= 8; ++j) {
        heights << (j ? ", [" : "[");
        for (int i = 0; i <= 8; ++i) {
            const float x = float(i) * 0.5f - 2.0f - cx, z = float(j) * 0.5f - 2.0f;
            heights << (i ? ", " : "") << amp * std::exp(-k * (x * x + z * z));
        }
        heights << "]";
    }
    heights << "]";
    return R"({"type": "heightfield", "spacing": [0.5, 0.5], "heights": )" + heights.str() + "}";
}

// A crate of 2 m tilted onto a mesh of 0.25 m cells: its box covers about 150 triangles, which
// the device collides in batches of 32 (RUBBLE_LEVEL_MAX_TRIANGLES) in the CPU's order.
TEST_F(DeviceLevelMesh, LargeCrateOnAFineMeshFollowsTheCpu) {
    const std::string scene = R"({"format": "rubble-scene", "version": 1,
        "simulation": {"collision": {"method": "sat"}},
        "shapes": {"floor": )" +
                              meshShape(flatMeshFile(40, 0.25f)) +
                              R"(,
                   "crate": {"type": "box", "half_extents": [1, 0.5, 1]}},
        "bodies": [{"name": "floor", "shape": "floor", "static": true},
                   {"name": "crate", "shape": "crate", "mass": 8, "position": [0.1, 1.2, 0.05],
                    "orientation": [0.98, 0.1, 0.05, 0.15]}]})";
    World d = device(scene), c = cpu(scene);
    const float worst = stepTwins(d, c, "crate", 180, 2e-3f);
    RecordProperty("worst_gap_m", std::to_string(worst));
    const std::uint32_t crate = *d.findBody("crate");
    EXPECT_NEAR(d.body(crate).position.y, 0.5f, 0.01f);
    EXPECT_LT(d.lastStep().largestPenetration, 0.01f);
}

// A gentle mound (neighbouring facets within a degree of each other, so that the CPU's contacts
// make one manifold as the device's do): the crate lands off its top, tips onto its slope and
// rests, on the device as on the CPU at every step.
TEST_F(DeviceLevelMesh, CrateLandsAndRestsOnAHeightFieldAsOnTheCpu) {
    const std::string scene = crateOn(fieldShape(0.15f, 0.1f, 0.0f), 0.6f,
                                      R"("position": [0.6, 0.8, 0.05],
                                         "orientation": [0.99, 0.0, 0.08, 0.1])");
    World d = device(scene), c = cpu(scene);
    const float worst = stepTwins(d, c, "crate", 240, 2e-3f);
    RecordProperty("worst_gap_m", std::to_string(worst));
    const std::uint32_t crate = *d.findBody("crate");
    EXPECT_LT(glm::length(d.body(crate).linearVelocity), 1e-3f);
    EXPECT_LT(d.lastStep().largestPenetration, 0.01f);
}

// A bump whose facets bend by up to 10 degrees under the crate: the CPU gives it a manifold per
// group of normals, the device one manifold with the deepest group's normal and the points of
// the groups near it. The crate lands on the bump's flank and rests within 2 cm of where it
// rests on the CPU, without sinking in.
TEST_F(DeviceLevelMesh, CrateRestsOnABumpNearWhereItRestsOnTheCpu) {
    const std::string scene =
        crateOn(fieldShape(0.3f, 0.8f, 0.8f), 0.6f, R"("position": [0.1, 0.9, 0.05])");
    World d = device(scene), c = cpu(scene);
    ASSERT_TRUE(test::stepWorld(d, 240));
    ASSERT_TRUE(test::stepWorld(c, 240));
    const std::uint32_t crate = *d.findBody("crate");
    EXPECT_LT(glm::length(d.body(crate).position - c.body(crate).position), 0.02f);
    EXPECT_LT(glm::length(d.body(crate).linearVelocity), 1e-3f);
    EXPECT_LT(d.lastStep().largestPenetration, 0.01f);
}

// A ball rolling and a capsule dropped across the seams of a flat mesh (their contacts are
// rubble/shared/triangle_contact.h's, as the hulls'): on the device as on the CPU at every step.
TEST_F(DeviceLevelMesh, BallAndCapsuleOnAFlatMeshFollowTheCpu) {
    const std::string scene = R"({"format": "rubble-scene", "version": 1,
        "simulation": {"collision": {"method": "sat"}},
        "shapes": {"floor": )" +
                              meshShape(flatMeshFile(20, 0.5f)) +
                              R"(,
                   "ball": {"type": "sphere", "radius": 0.2},
                   "pill": {"type": "capsule", "radius": 0.15, "half_height": 0.3}},
        "bodies": [{"name": "floor", "shape": "floor", "static": true},
                   {"name": "ball", "shape": "ball", "mass": 1, "position": [-2, 0.5, 0.1],
                    "linear_velocity": [2, 0, 0.5]},
                   {"name": "pill", "shape": "pill", "mass": 1, "position": [1.3, 0.6, 0.2],
                    "orientation": [0.70710678, 0.1, 0, 0.70710678]}]})";
    World d = device(scene), c = cpu(scene);
    const std::uint32_t ball = *c.findBody("ball"), pill = *c.findBody("pill");
    float worst = 0.0f;
    for (int i = 0; i < 180; ++i) {
        ASSERT_TRUE(test::stepWorld(d, 1));
        ASSERT_TRUE(test::stepWorld(c, 1));
        for (const std::uint32_t b : {ball, pill})
            worst = std::max(worst, glm::length(d.body(b).position - c.body(b).position));
    }
    EXPECT_LT(worst, 2e-3f);
    EXPECT_NEAR(d.body(ball).position.y, 0.2f, 0.005f);
    EXPECT_GT(d.body(ball).position.x, -1.0f) << "the ball rolls over the seams";
    EXPECT_NEAR(d.body(pill).position.y, 0.15f, 0.005f);
    EXPECT_LT(d.lastStep().largestPenetration, 0.01f);
}

// A box sliding at 5 m/s over 100 x 100 quads of 0.5 m: no bump on the seams (vertical speed
// under 1 mm/s) and the plane's friction deceleration within 1%.
TEST_F(DeviceLevelMesh, BoxSlidesOverAFlatMeshWithoutBumps) {
    const std::string at = R"("position": [0.13, 0.3, 0.07])";
    World mesh = device(crateOn(meshShape(flatMeshFile(100, 0.5f)), 0.3f, at));
    World plane =
        device(crateOn(R"({"type": "plane", "normal": [0, 1, 0], "offset": 0})", 0.3f, at));
    const std::uint32_t crate = *mesh.findBody("crate");
    test::expectSlidesAsOnAPlane(plane, mesh, crate);
}

} // namespace
} // namespace rubble
