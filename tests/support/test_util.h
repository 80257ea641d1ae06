// tests/support/test_util.h: helpers shared by the test binaries: worlds from inline scene text,
// and running the `rubble` command.
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rubble/world.h"

namespace rubble::test {

/// A world from scene JSON text; fails the test when it does not load.
inline World worldFromText(const std::string& json, const RunOptions& run = {}) {
    Result<Scene> scene = parseScene(json, "inline.json", ".");
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
    if (!scene.ok()) std::abort();
    Result<World> world = World::create(*scene, run);
    EXPECT_TRUE(world.ok()) << (world.ok() ? "" : world.error().describe());
    if (!world.ok()) std::abort();
    return std::move(*world);
}

/// The error a scene text gives when loaded and built; an Internal error "loaded" if none.
inline Error sceneError(const std::string& json) {
    Result<Scene> scene = parseScene(json, "inline.json", ".");
    if (!scene) return scene.error();
    Result<World> world = World::create(*scene);
    if (!world) return world.error();
    return makeError(ErrorKind::Internal, "", "loaded");
}

/// Steps n times; false (with a test failure) when a step fails.
inline bool stepWorld(World& world, int n) {
    for (int i = 0; i < n; ++i) {
        const Status s = world.step();
        EXPECT_TRUE(s.ok()) << "step " << i << ": " << (s.ok() ? "" : s.error().describe());
        if (!s.ok()) return false;
    }
    return true;
}

/// Each body's position, in body order.
inline std::vector<glm::vec3> positionsOf(const World& world) {
    std::vector<glm::vec3> out;
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) out.push_back(world.body(i).position);
    return out;
}

/// How far the dynamic bodies (all but body 0, the floor) moved from `start` (positionsOf):
/// the largest drop and distance aside, m, and how many are asleep.
struct Settled {
    float drop = 0.0f, aside = 0.0f;
    std::uint32_t asleep = 0;
};
inline Settled settledSince(const World& world, const std::vector<glm::vec3>& start) {
    Settled s;
    for (std::uint32_t i = 1; i < world.bodyCount(); ++i) {
        const glm::vec3 moved = world.body(i).position - start[i];
        s.drop = std::max(s.drop, -moved.y);
        s.aside = std::max(s.aside, std::hypot(moved.x, moved.z));
        s.asleep += world.body(i).asleep ? 1u : 0u;
    }
    return s;
}

/// Output and exit status of a command run through the shell.
struct CommandResult {
    int exitCode = -1;
    std::string output; ///< stdout and stderr together
};

inline CommandResult runShell(const std::string& command) {
    CommandResult r;
    std::FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buf;
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
    const int status = pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

/// Runs the built `rubble` binary with arguments.
inline CommandResult runRubble(const std::string& args) {
    return runShell(std::string(RUBBLE_BINARY) + " " + args);
}

/// A fresh, empty folder for one test. ctest runs the tests of one binary as parallel processes,
/// so the folder is named after the running test as well as `name`: two tests asking for the same
/// name never empty each other's folder.
inline std::string tempDir(const std::string& name) {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string who = test ? std::string(test->test_suite_name()) + "." + test->name() : "none";
    for (char& c : who)
        if (c == '/') c = '_';
    // Under the build directory, beside the command under test: two builds (the plain and the
    // sanitized one, or two checkouts) running the same case at once do not share a directory.
    const std::string binary = RUBBLE_BINARY;
    const std::string dir =
        binary.substr(0, binary.rfind('/')) + "/test-tmp/rubble_" + name + "_" + who;
    runShell("rm -rf '" + dir + "' && mkdir -p '" + dir + "'");
    return dir;
}

inline void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

inline std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The rows of a CSV text (the trajectory and comparison files: no quoting), split at commas.
inline std::vector<std::vector<std::string>> csvRows(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells;
        std::istringstream l(line);
        for (std::string cell; std::getline(l, cell, ',');) cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

} // namespace rubble::test
