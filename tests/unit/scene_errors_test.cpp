// tests/unit/scene_errors_test.cpp: every class of bad scene input gives exit status 2 from
// `rubble validate` and a message naming the file and the JSON path of the field.
#include <cstring>

#include <gtest/gtest.h>

#include "support/test_util.h"

namespace rubble {
namespace {

// A valid scene with one token to replace: each case swaps a fragment of it.
const std::string kBase = R"({
  "format": "rubble-scene",
  "version": 1,
  "simulation": {"dt": 0.01, "steps": 10},
  "materials": {"ice": {"friction": 0.05}},
  "shapes": {
    "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
    "ball": {"type": "sphere", "radius": 0.25},
    "ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0}
  },
  "bodies": [
    {"name": "floor", "shape": "ground", "static": true},
    {"name": "c0", "shape": "crate", "mass": 1.0, "position": [0, 0.5, 0]},
    {"name": "b0", "shape": "ball", "density": 500, "material": "ice", "position": [0, 2, 0]}
  ]
})";

struct BadCase {
    const char* name;
    const char* find;      // fragment of kBase to replace ("" appends nothing)
    const char* replace;   // what goes in its place
    const char* where;     // expected in the message after the file name
    const char* message;   // expected in the message
};

const BadCase kCases[] = {
    {"MalformedJson", "\"steps\": 10}", "\"steps\": 10,}", "", "line 4, column"},
    {"UnknownTopLevelKey", "\"version\": 1,", "\"version\": 1, \"bodys\": [],", "bodys", "unknown key"},
    {"UnknownNestedKey", "\"mass\": 1.0,", "\"mas\": 1.0,", "bodies[1].mas", "unknown key"},
    {"WrongType", "\"dt\": 0.01", "\"dt\": \"fast\"", "simulation.dt", "expected a number"},
    {"WrongTypeInteger", "\"steps\": 10", "\"steps\": 10.5", "simulation.steps", "expected an integer"},
    {"InfiniteNumber", "\"mass\": 1.0", "\"mass\": 1e999", "bodies[1].mass", "finite"},
    {"TooLargeForFloat", "\"mass\": 1.0", "\"mass\": 1e60", "bodies[1].mass", "single precision"},
    {"ZeroMass", "\"mass\": 1.0", "\"mass\": 0", "bodies[1].mass", "greater than 0"},
    {"NegativeMass", "\"mass\": 1.0", "\"mass\": -2", "bodies[1].mass", "greater than 0"},
    {"NegativeDensity", "\"density\": 500", "\"density\": -500", "bodies[2].density", "greater than 0"},
    {"NegativeExtent", "[0.5, 0.5, 0.5]", "[0.5, -0.5, 0.5]", "shapes.crate.half_extents[1]", "between 0.0001 and 100000 m, got -0.5"},
    {"ZeroRadius", "\"radius\": 0.25", "\"radius\": 0", "shapes.ball.radius", "between 0.0001 and 100000 m, got 0"},
    {"ZeroDt", "\"dt\": 0.01", "\"dt\": 0", "simulation.dt", "greater than 0"},
    {"NegativeDt", "\"dt\": 0.01", "\"dt\": -0.01", "simulation.dt", "greater than 0"},
    {"DtZeroAsFloat", "\"dt\": 0.01", "\"dt\": 1e-300", "simulation.dt", "must be greater than 0, got 1e-300 (0 as a float)"},
    {"DtBelowFloat", "\"dt\": 0.01", "\"dt\": 1e-40", "simulation.dt", "too small for single precision"},
    {"SlopBelowFloat", "\"dt\": 0.01", "\"dt\": 0.01, \"solver\": {\"slop\": 1e-300}", "simulation.solver.slop", "too small for single precision"},
    {"ExtentBelowRange", "[0.5, 0.5, 0.5]", "[1e-20, 0.5, 0.5]", "shapes.crate.half_extents[0]", "between 0.0001 and 100000 m"},
    {"ExtentAboveRange", "[0.5, 0.5, 0.5]", "[0.5, 1e15, 0.5]", "shapes.crate.half_extents[1]", "between 0.0001 and 100000 m"},
    {"RadiusAboveRange", "\"radius\": 0.25", "\"radius\": 1e6", "shapes.ball.radius", "between 0.0001 and 100000 m"},
    {"SpacingBelowRange", "\"steps\": 10", "\"steps\": 10, \"collision\": {\"particle_spacing\": 1e-9}", "simulation.collision.particle_spacing", "must be between 0.0001 and 100000, got 1e-09"},
    {"HullBeyondRange", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"convex\", \"vertices\": [[0,0,0],[1e6,0,0],[0,1,0],[0,0,1]]", "shapes.ball.vertices", "farther than 100000 m"},
    {"HullBelowRange", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"convex\", \"vertices\": [[0,0,0],[1e-6,0,0],[0,1e-6,0],[0,0,1e-6]]", "shapes.ball.vertices", "span less than 0.0001 m"},
    {"MassBeyondFloat", "\"mass\": 1.0", "\"mass\": 3e38", "bodies[1]", "single precision cannot hold"},
    {"DensityBeyondFloat", "\"density\": 500", "\"density\": 1e-37", "bodies[2]", "its density gives"},
    {"RagdollScale", "\"bodies\": [", "\"generators\": [{\"type\": \"ragdoll\", \"position\": [0, 3, 0], \"scale\": 1e-9}], \"bodies\": [", "generators[0].scale", "between 0.1 and 100"},
    {"UnknownShape", "\"shape\": \"crate\"", "\"shape\": \"crat\"", "bodies[1].shape", "no shape named \"crat\""},
    {"UnknownMaterial", "\"material\": \"ice\"", "\"material\": \"snow\"", "bodies[2].material", "no material named \"snow\""},
    {"UnknownShapeType", "\"type\": \"sphere\"", "\"type\": \"ellipsoid\"", "shapes.ball.type", "unknown shape type"},
    {"UnknownEnum", "\"steps\": 10", "\"steps\": 10, \"integrator\": \"rk4\"", "simulation.integrator", "unknown value \"rk4\""},
    {"DuplicateBodyName", "\"name\": \"b0\"", "\"name\": \"c0\"", "bodies[2].name", "duplicate body name \"c0\""},
    {"DuplicateShapeName", "\"ball\": {", "\"crate\": {", "shapes.crate", "given twice"},
    {"ZeroQuaternion", "\"position\": [0, 0.5, 0]", "\"position\": [0, 0.5, 0], \"orientation\": [0, 0, 0, 0]", "bodies[1].orientation", "cannot be normalised"},
    {"ShortQuaternion", "\"position\": [0, 0.5, 0]", "\"position\": [0, 0.5, 0], \"orientation\": [1, 0, 0]", "bodies[1].orientation", "[w, x, y, z]"},
    {"ShortVector", "\"position\": [0, 2, 0]", "\"position\": [0, 2]", "bodies[2].position", "3 numbers"},
    {"MissingMeshFile", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"mesh\", \"file\": \"no/such.obj\"", "shapes.ball.file", "mesh file not found"},
    {"CoplanarHull", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"convex\", \"vertices\": [[0,0,0],[1,0,0],[0,1,0],[1,1,0],[2,3,0]]", "shapes.ball.vertices", "coplanar"},
    {"TooFewHullPoints", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"convex\", \"vertices\": [[0,0,0],[1,0,0],[0,1,0]]", "shapes.ball.vertices", "at least 4 points"},
    {"UnsupportedVersion", "\"version\": 1", "\"version\": 2", "version", "unsupported version 2"},
    {"WrongFormat", "\"rubble-scene\"", "\"bullet-scene\"", "format", "expected \"rubble-scene\""},
    {"StaticWithMass", "\"static\": true", "\"static\": true, \"mass\": 3", "bodies[0].mass", "static body"},
    {"PlaneOnDynamicBody", "\"static\": true", "\"mass\": 3", "bodies[0].shape", "static bodies only"},
    {"KinematicWithMass", "\"mass\": 1.0,", "\"kinematic\": true, \"mass\": 1.0,", "bodies[1].mass", "kinematic body has infinite mass"},
    {"KinematicWithDensity", "\"density\": 500,", "\"kinematic\": true, \"density\": 500,", "bodies[2].density", "kinematic body has infinite mass"},
    {"KinematicAndStatic", "\"static\": true", "\"static\": true, \"kinematic\": true", "bodies[0].kinematic", "static or kinematic, not both"},
    {"KinematicNotBoolean", "\"mass\": 1.0,", "\"kinematic\": 1,", "bodies[1].kinematic", "expected"},
    {"CapsuleZeroRadius", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"capsule\", \"radius\": 0, \"half_height\": 0.3", "shapes.ball.radius", "between 0.0001 and 100000 m, got 0"},
    {"CapsuleNegativeRadius", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"capsule\", \"radius\": -0.2, \"half_height\": 0.3", "shapes.ball.radius", "between 0.0001 and 100000 m"},
    {"CapsuleNegativeHalfHeight", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"capsule\", \"radius\": 0.2, \"half_height\": -1", "shapes.ball.half_height", "0 or more"},
    {"CapsuleWithoutHalfHeight", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"capsule\", \"radius\": 0.2", "shapes.ball.half_height", "required"},
    {"MassAndDensity", "\"mass\": 1.0", "\"mass\": 1.0, \"density\": 3", "bodies[1].density", "not both"},
    {"NoMassNorDensity", "\"density\": 500, ", "", "bodies[2]", "needs \"mass\" or \"density\""},
    {"MissingShape", "\"shape\": \"crate\", ", "", "bodies[1].shape", "required"},
    {"RestitutionAboveOne", "\"friction\": 0.05", "\"restitution\": 1.5", "materials.ice.restitution", "between 0 and 1"},
    {"ZeroPlaneNormal", "\"normal\": [0, 1, 0]", "\"normal\": [0, 0, 0]", "shapes.ground.normal", "zero length"},
    {"BadGeneratorCount", "\"bodies\": [", "\"generators\": [{\"type\": \"grid\", \"shape\": \"crate\", \"mass\": 1, \"count\": [2, 0, 2]}], \"bodies\": [", "generators[0].count", "integer from 1"},
    {"HeightFieldNonFinite", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"heightfield\", \"spacing\": [0.5, 0.5], \"heights\": [[0, 1], [0, 1e999]]", "shapes.ball.heights[1][1]", "finite"},
    {"HeightFieldRagged", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"heightfield\", \"spacing\": [0.5, 0.5], \"heights\": [[0, 1, 2], [0, 1]]", "shapes.ball.heights[1]", "the same count"},
    {"HeightFieldTooFew", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"heightfield\", \"spacing\": [0.5, 0.5], \"heights\": [[0, 1]]", "shapes.ball.heights", "at least 2 x 2"},
    {"HeightFieldZeroSpacing", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"heightfield\", \"spacing\": [0.5, 0], \"heights\": [[0, 1], [0, 1]]", "shapes.ball.spacing", "expected two spacings"},
    {"HeightFieldMissingPng", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"heightfield\", \"spacing\": [1, 1], \"file\": \"no/such.png\", \"height_scale\": 2", "shapes.ball.file", "not a readable PNG"},
    {"HeightFieldOnDynamicBody", "\"type\": \"sphere\", \"radius\": 0.25", "\"type\": \"heightfield\", \"spacing\": [0.5, 0.5], \"heights\": [[0, 1], [0, 1]]", "bodies[2].shape", "heightfield shapes are for static bodies only"},
    {"UnknownJointBody", "\"bodies\": [", "\"joints\": [{\"type\": \"ball\", \"a\": \"c0\", \"b\": \"ghost\", \"anchor\": [0, 1, 0]}], \"bodies\": [", "joints[0].b", "no body named \"ghost\""},
};

class SceneErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(SceneErrors, ExitTwoAndNameTheField) {
    const BadCase& c = GetParam();
    std::string text = kBase;
    const std::size_t at = text.find(c.find);
    ASSERT_NE(at, std::string::npos) << "fragment not in the base scene: " << c.find;
    text.replace(at, std::strlen(c.find), c.replace);
    const std::string dir = test::tempDir(std::string("bad_") + c.name);
    const std::string file = dir + "/scene.json";
    test::writeText(file, text);
    const test::CommandResult r = test::runRubble("validate '" + file + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    const std::string where = std::string(c.where).empty() ? file : file + ": " + c.where;
    EXPECT_NE(r.output.find(where), std::string::npos) << "expected \"" << where << "\" in: " << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << "expected \"" << c.message << "\" in: " << r.output;
    ASSERT_FALSE(r.output.empty());
    EXPECT_EQ(r.output.back(), '\n') << "the message does not end its line: " << r.output;
}

INSTANTIATE_TEST_SUITE_P(BadInput, SceneErrors, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<BadCase>& i) { return std::string(i.param.name); });

TEST(SceneErrorsBase, TheBaseSceneIsValid) {
    const std::string dir = test::tempDir("bad_base");
    test::writeText(dir + "/scene.json", kBase);
    const test::CommandResult r = test::runRubble("validate '" + dir + "/scene.json'");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("bodies: 3 (1 static, 2 dynamic)"), std::string::npos) << r.output;
}

// JSON nested far deeper than any scene is refused while parsing, naming where it happens; the
// error message does not walk the value (a 100,000-deep array overflowed the stack there).
TEST(SceneErrorsBase, DeeplyNestedJsonIsRefused) {
    for (const std::size_t depth : {65, 100'000}) {
        std::string text = kBase;
        const std::string nested = std::string(depth, '[') + std::string(depth, ']');
        text.replace(text.find("\"version\": 1,"), 13, "\"version\": 1, \"name\": " + nested + ",");
        const std::string dir = test::tempDir("bad_deep");
        test::writeText(dir + "/scene.json", text);
        const test::CommandResult r = test::runRubble("validate '" + dir + "/scene.json'");
        EXPECT_EQ(r.exitCode, 2) << r.output.substr(0, 400);
        EXPECT_NE(r.output.find("scene.json: name[0][0][0]...: the JSON is nested more than 64 levels"),
                  std::string::npos)
            << r.output.substr(0, 400);
    }
    // 64 levels parse, and the type error shows the value shortened.
    std::string text = kBase;
    text.replace(text.find("\"version\": 1,"), 13,
                 "\"version\": 1, \"name\": " + std::string(63, '[') + std::string(63, ']') + ",");
    const std::string dir = test::tempDir("bad_deep64");
    test::writeText(dir + "/scene.json", text);
    const test::CommandResult r = test::runRubble("validate '" + dir + "/scene.json'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("name: expected a string, got an array [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[..."),
              std::string::npos)
        << r.output;
}

TEST(SceneErrorsBase, MissingSceneFile) {
    const test::CommandResult r = test::runRubble("validate /no/such/scene.json");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("/no/such/scene.json: scene file not found"), std::string::npos) << r.output;
}

TEST(SceneErrorsBase, BadCommandLineValueIsExitTwo) {
    const std::string dir = test::tempDir("bad_cli");
    test::writeText(dir + "/scene.json", kBase);
    test::CommandResult r = test::runRubble("run '" + dir + "/scene.json' --dt -1");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--dt"), std::string::npos) << r.output;
    r = test::runRubble("run '" + dir + "/scene.json' --integrator rk4");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--integrator: unknown value \"rk4\""), std::string::npos) << r.output;
    r = test::runRubble("run '" + dir + "/scene.json' --out traj.txt");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find(".csv or .jsonl"), std::string::npos) << r.output;
    r = test::runRubble("run '" + dir + "/scene.json' --steps banana");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    r = test::runRubble("run '" + dir + "/scene.json' --dt 1e-40");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--dt: is too small for single precision"), std::string::npos) << r.output;
    r = test::runRubble("run '" + dir + "/scene.json' --particle-spacing 1e-9");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--particle-spacing: must be between"), std::string::npos) << r.output;
}

} // namespace
} // namespace rubble
