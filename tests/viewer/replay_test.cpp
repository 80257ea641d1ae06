// tests/viewer/replay_test.cpp: recorded trajectories read back against a scene: poses by body
// name, and malformed files refused with the file and line.
#include <gtest/gtest.h>

#include "host/viewer/replay.h"
#include "support/test_util.h"

namespace rubble {
namespace {

const char* kScene = R"({"format": "rubble-scene", "version": 1, "name": "two",
  "shapes": {"ball": {"type": "sphere", "radius": 0.1}},
  "bodies": [{"name": "a", "shape": "ball", "mass": 1, "position": [0, 1, 0]},
             {"name": "b", "shape": "ball", "mass": 1, "position": [5, 1, 0]}]})";

const char* kHeader = "step,time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";

Result<viewer::Replay> load(const std::string& name, const std::string& text) {
    static World world = test::worldFromText(kScene);
    const std::string dir = test::tempDir("replay");
    const std::string path = dir + "/" + name;
    test::writeText(path, text);
    return viewer::Replay::load(path, world);
}

std::string errorOf(const Result<viewer::Replay>& r) {
    return r.ok() ? std::string("loaded") : r.error().describe();
}

TEST(Replay, ReadsCsvStepsByBodyName) {
    const Result<viewer::Replay> r =
        load("t.csv", std::string(kHeader) + "0,0,a,0,1,0,1,0,0,0,0,0,0,0,0,0\n"
                                             "0,0,b,5,1,0,1,0,0,0,0,0,0,0,0,0\n"
                                             "2,0.02,b,5,0.5,0,0,1,0,0,0,0,0,0,0,0\n"
                                             "2,0.02,a,1,2,3,2,0,0,0,0,0,0,0,0,0\n");
    ASSERT_TRUE(r.ok()) << errorOf(r);
    ASSERT_EQ(r->frames().size(), 2u);
    const viewer::ReplayFrame& f = r->frames()[1];
    EXPECT_EQ(f.step, 2);
    EXPECT_NEAR(f.time, 0.02, 1e-12);
    EXPECT_FLOAT_EQ(f.poses[0].position.x, 1.0f);
    EXPECT_FLOAT_EQ(f.poses[0].position.z, 3.0f);
    EXPECT_FLOAT_EQ(f.poses[0].orientation.w, 1.0f); // normalised from (2, 0, 0, 0)
    EXPECT_FLOAT_EQ(f.poses[1].position.y, 0.5f);
    EXPECT_FLOAT_EQ(f.poses[1].orientation.x, 1.0f); // file order w, x, y, z
    EXPECT_EQ(r->atStep(1).step, 0);
    EXPECT_EQ(r->atStep(7).step, 2);
}

TEST(Replay, ReadsJsonLines) {
    const Result<viewer::Replay> r = load(
        "t.jsonl",
        R"({"step":0,"time":0,"bodies":[{"body":"b","px":5,"py":1,"pz":0,"qw":1,"qx":0,"qy":0,"qz":0}]})"
        "\n"
        R"({"step":10,"time":0.1,"bodies":[{"body":"b","px":6,"py":1,"pz":0,"qw":1,"qx":0,"qy":0,"qz":0}]})"
        "\n");
    ASSERT_TRUE(r.ok()) << errorOf(r);
    ASSERT_EQ(r->frames().size(), 2u);
    EXPECT_FLOAT_EQ(r->frames()[1].poses[1].position.x, 6.0f);
    // Body a is not in the file: it stays where the scene put it.
    EXPECT_FLOAT_EQ(r->frames()[1].poses[0].position.y, 1.0f);
}

TEST(Replay, MalformedFilesNameTheFileAndLine) {
    const std::string row = "0,0,a,0,1,0,1,0,0,0,0,0,0,0,0,0\n";
    struct Case {
        std::string name, text, expected;
    } cases[] = {
        {"bad_header.csv", "step,time,body\n" + row, "bad_header.csv:1: expected the header"},
        {"short.csv", kHeader + row + "1,0.01,a,0,1\n", "short.csv:3: expected 16 fields, got 5"},
        {"number.csv", kHeader + std::string("0,0,a,zero,1,0,1,0,0,0,0,0,0,0,0,0\n"),
         "number.csv:2: px: not a number: \"zero\""},
        {"who.csv", kHeader + std::string("0,0,c,0,1,0,1,0,0,0,0,0,0,0,0,0\n"),
         "who.csv:2: body \"c\" is not in the scene two"},
        {"back.csv", kHeader + std::string("5,0,a,0,1,0,1,0,0,0,0,0,0,0,0,0\n") + row,
         "back.csv:3: step 0 comes after step 5"},
        {"nan.csv", kHeader + std::string("0,0,a,nan,1,0,1,0,0,0,0,0,0,0,0,0\n"),
         "nan.csv:2: px of body \"a\" is not a finite number"},
        {"empty.csv", "", "empty.csv:1: the file is empty"},
        {"header_only.csv", kHeader, "header_only.csv: the trajectory has no steps"},
        {"broken.jsonl", "{\"step\":0,\"time\":0,\"bodies\":[]}\n{\"step\":1,",
         "broken.jsonl:2: not a JSON object"},
        {"field.jsonl",
         R"({"step":0,"time":0,"bodies":[{"body":"a","px":0,"py":"1"}]})"
         "\n",
         "field.jsonl:1: bodies[0].py: expected a number"},
        {"t.txt", row, "--replay"},
    };
    for (const Case& c : cases) {
        const Result<viewer::Replay> r = load(c.name, c.text);
        ASSERT_FALSE(r.ok()) << c.name;
        EXPECT_EQ(r.error().kind, ErrorKind::BadInput) << c.name;
        EXPECT_NE(r.error().describe().find(c.expected), std::string::npos)
            << c.name << ": " << r.error().describe();
    }
}

TEST(Replay, MissingFileIsNamed) {
    static World world = test::worldFromText(kScene);
    const Result<viewer::Replay> r = viewer::Replay::load("/nonexistent/t.csv", world);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().describe().find("/nonexistent/t.csv"), std::string::npos);
}

} // namespace
} // namespace rubble
