// tests/unit/option_table_test.cpp: host/core/option_table: every option reads its default back
// from text and from a scene file, reaches its own member, and is refused out of range with the
// same message in a scene file, on the command line and in `rubble compare`; the docs' table and
// `rubble run --help` are the table's.
#include <set>

#include <gtest/gtest.h>

#include "host/core/option_table.h"
#include "support/test_util.h"

namespace rubble {
namespace {

// Every member different from its default, so that a read that lands nowhere shows.
SimulationOptions otherSimulation() {
    SimulationOptions s;
    s.dt = 0.01f;
    s.steps = 7;
    s.gravity = glm::vec3(1.0f, 2.0f, -3.5f);
    s.integrator = Integrator::Explicit;
    s.backend = Backend::OpenCl;
    s.collision.method = CollisionMethod::Particles;
    s.collision.particleSpacing = 0.3f;
    s.collision.recycleContacts = !SimulationOptions{}.collision.recycleContacts;
    s.solver.type = SolverType::Lemke;
    s.solver.iterations = 3;
    s.solver.baumgarte = 0.5f;
    s.solver.slop = 0.01f;
    s.solver.relaxation = 1.5f;
    s.solver.warmStart = false;
    s.solver.substeps = 9;
    s.solver.relaxIterations = 3;
    s.solver.contactHertz = 45.0f;
    s.solver.dampingRatio = 0.5f;
    s.solver.jointHertz = 20.0f;
    s.solver.jointDampingRatio = 7.0f;
    s.solver.maxPushSpeed = 0.75f;
    s.coupling = Coupling::TwoWay;
    s.continuous = false;
    s.sleep = false;
    return s;
}

RunOptions otherRun() {
    RunOptions r;
    r.device = "1";
    r.kernelDir = "kernels";
    r.deterministic = true;
    r.pgsBlocks = 3;
    r.pgsColoring = PgsColoring::Device;
    r.bodySleep = true;
    r.buildOptions = "-cl-opt-disable";
    return r;
}

std::optional<OptionValue> defaultOf(const Option& o) {
    return o.load(SimulationOptions{}, RunOptions{});
}

// {"a": {"b": value}} for the key "a.b".
std::string nestedJson(std::string_view key, const std::string& value) {
    const std::size_t dot = key.find('.');
    if (dot == std::string_view::npos) return "\"" + std::string(key) + "\": " + value;
    return "\"" + std::string(key.substr(0, dot)) + "\": {" +
           nestedJson(key.substr(dot + 1), value) + "}";
}

std::string sceneWith(std::string_view key, const std::string& value) {
    return R"({"format": "rubble-scene", "version": 1, "simulation": {)" + nestedJson(key, value) +
           "}}";
}

TEST(OptionTable, KeysAndNamesAreUniqueAndEveryOptionSaysWhatItIs) {
    std::set<std::string_view> keys, names;
    for (const Option& o : optionTable()) {
        EXPECT_FALSE(o.help.empty()) << o.name;
        EXPECT_TRUE(names.insert(o.name).second) << "name given twice: " << o.name;
        if (!o.alias.empty()) {
            EXPECT_TRUE(names.insert(o.alias).second) << o.alias;
        }
        EXPECT_EQ(o.key.empty(), o.scope == OptionScope::Run) << o.name;
        if (!o.key.empty()) {
            EXPECT_TRUE(keys.insert(o.key).second) << "key given twice: " << o.key;
            EXPECT_EQ(findOptionByKey(o.key), &o);
        }
        EXPECT_EQ(o.kind == OptionKind::Choice, !o.choices.empty()) << o.name;
        EXPECT_EQ(findOptionByName(o.name), &o);
    }
    EXPECT_EQ(findOptionByName("particle_spacing"), findOptionByName("particle-spacing"));
    EXPECT_EQ(findOptionByName("colour"), nullptr);
    EXPECT_EQ(findOptionByKey("solver"), nullptr); // a group, not an option
}

TEST(OptionTable, EveryOptionReadsItsDefaultBackFromText) {
    for (const Option& o : optionTable()) {
        const std::optional<OptionValue> def = defaultOf(o);
        if (!def) {
            EXPECT_FALSE(o.unsetText.empty()) << o.name << " is unset by default and says nothing";
            continue;
        }
        SimulationOptions sim = otherSimulation();
        RunOptions run = otherRun();
        ASSERT_NE(o.load(sim, run), def) << "the test's other value of " << o.name
                                         << " is its default";
        const Status s = assignOptionText(o, optionText(*def), "test", OptionTarget{&sim, &run});
        ASSERT_TRUE(s.ok()) << o.name << ": " << s.error().describe();
        EXPECT_EQ(o.load(sim, run), def) << o.name << " from \"" << optionText(*def) << "\"";
        EXPECT_EQ(optionDefaultText(o), optionText(*def));
    }
    // The shortest text of 1/60 s reads back to the same float.
    const Option& dt = *findOptionByKey("dt");
    SimulationOptions sim = otherSimulation();
    ASSERT_TRUE(assignOptionText(dt, optionDefaultText(dt), "test", OptionTarget{&sim}).ok());
    EXPECT_EQ(sim.dt, 1.0f / 60.0f);
}

TEST(OptionTable, EverySceneKeyReachesItsMember) {
    const SimulationOptions other = otherSimulation();
    for (const Option& o : optionTable()) {
        if (o.scope != OptionScope::Simulation) continue;
        const std::string text = sceneWith(o.key, optionJson(*o.load(other, RunOptions{})));
        Result<Scene> scene = parseScene(text, "inline.json", ".");
        ASSERT_TRUE(scene.ok()) << text << "\n" << scene.error().describe();
        EXPECT_EQ(o.load(scene->simulation, RunOptions{}), o.load(other, RunOptions{})) << text;
        // ... and only it: every other option keeps its default.
        for (const Option& p : optionTable()) {
            if (&p != &o && p.scope == OptionScope::Simulation) {
                EXPECT_EQ(p.load(scene->simulation, RunOptions{}), defaultOf(p))
                    << o.key << " changed " << p.key;
            }
        }
    }
}

TEST(OptionTable, TheDefaultsAreThoseOfOptionsH) {
    // The table has no defaults of its own: a scene without `simulation` is a default one.
    Result<Scene> scene = parseScene(R"({"format": "rubble-scene", "version": 1})", "a.json", ".");
    ASSERT_TRUE(scene.ok());
    for (const Option& o : optionTable()) {
        if (o.scope == OptionScope::Simulation) {
            EXPECT_EQ(o.load(scene->simulation, RunOptions{}), defaultOf(o)) << o.key;
        }
    }
    EXPECT_EQ(optionDefaultText(*findOptionByKey("collision.particle_spacing")), "0.1");
    EXPECT_EQ(optionDefaultText(*findOptionByKey("solver.iterations")), "10");
    EXPECT_EQ(optionDefaultText(*findOptionByKey("gravity")), "0,-9.81,0");
}

struct OutOfRange {
    const char* key;     // scene key, or the name of a run option
    const char* text;    // as written on the command line and in the file
    const char* message; // what all paths say after naming the field
};

const OutOfRange kOutOfRange[] = {
    {"dt", "0", "must be greater than 0, got 0"},
    {"dt", "-0.01", "must be greater than 0, got -0.01"},
    // Checked as floats: 1e-300 s is 0 s, 1e40 s is infinite.
    {"dt", "1e-300", "must be greater than 0, got 1e-300 (0 as a float)"},
    {"dt", "1e+40", "is too large for single precision, got 1e+40"},
    {"steps", "-1", "must be between 0 and 1000000000, got -1"},
    {"steps", "1000000001", "must be between 0 and 1000000000, got 1000000001"},
    {"integrator", "rk4", "unknown value \"rk4\" (expected symplectic or explicit)"},
    {"backend", "cuda", "unknown value \"cuda\" (expected cpu or opencl)"},
    {"collision.method", "voxels", "unknown value \"voxels\" (expected sat or particles)"},
    // A subnormal float keeps fewer digits.
    {"dt", "1e-40", "is too small for single precision (other than 0, at least 1.2e-38 in size), "
                    "got 1e-40"},
    {"collision.particle_spacing", "0", "must be between 0.0001 and 100000, got 0"},
    {"collision.particle_spacing", "1e-50",
     "must be between 0.0001 and 100000, got 1e-50 (0 as a float)"},
    {"collision.particle_spacing", "1e+06", "must be between 0.0001 and 100000, got 1000000"},
    {"solver.type", "sor",
     "unknown value \"sor\" (expected pgs, jacobi, lcp-jacobi, lemke or soft-step)"},
    {"solver.iterations", "0", "must be between 1 and 100000, got 0"},
    {"solver.iterations", "100001", "must be between 1 and 100000, got 100001"},
    {"solver.baumgarte", "1.5", "must be between 0 and 1, got 1.5"},
    {"solver.slop", "-0.001", "must be 0 or more, got -0.001"},
    {"solver.relaxation", "2", "must be greater than 0 and below 2, got 2"},
    {"solver.relaxation", "0", "must be greater than 0 and below 2, got 0"},
    {"coupling", "both", "unknown value \"both\" (expected one-way or two-way)"},
};

// A floor and a box, one step.
const char* kTinyScene = R"({"format": "rubble-scene", "version": 1,
  "simulation": {"steps": 1},
  "shapes": {"crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
  "bodies": [{"name": "a", "shape": "crate", "mass": 1}]})";

TEST(OptionTable, OutOfRangeIsTheSameErrorInAFileOnTheCommandLineAndInCompare) {
    const std::string dir = test::tempDir("option_range");
    test::writeText(dir + "/s.json", kTinyScene);
    for (const OutOfRange& c : kOutOfRange) {
        const Option* o = findOptionByKey(c.key);
        ASSERT_NE(o, nullptr) << c.key;
        SCOPED_TRACE(std::string(c.key) + " = " + c.text);

        // The table itself.
        SimulationOptions sim;
        const Status table = assignOptionText(*o, c.text, "here", OptionTarget{&sim});
        ASSERT_FALSE(table.ok());
        EXPECT_EQ(table.error().message, c.message);
        EXPECT_EQ(table.error().where, "here");

        // A scene file: names the JSON path.
        const bool isText = o->kind == OptionKind::Choice;
        const std::string json = isText ? "\"" + std::string(c.text) + "\"" : c.text;
        const Result<Scene> scene = parseScene(sceneWith(c.key, json), "inline.json", ".");
        ASSERT_FALSE(scene.ok());
        EXPECT_EQ(scene.error().describe(),
                  "inline.json: simulation." + std::string(c.key) + ": " + c.message);

        // The command line: names the flag.
        if (o->uses & kUseFlag) {
            const test::CommandResult r = test::runRubble("run " + dir + "/s.json --quiet --" +
                                                          std::string(o->name) + " " + c.text);
            EXPECT_EQ(r.exitCode, 2) << r.output;
            EXPECT_NE(r.output.find("rubble: --" + std::string(o->name) + ": " + c.message + "\n"),
                      std::string::npos)
                << r.output;
        }
        // rubble compare: names the setting.
        if (o->uses & kUseCompare) {
            const std::string setting = std::string(o->name) + "=" + c.text;
            const test::CommandResult r = test::runRubble(
                "compare " + dir + "/s.json --steps 1 --a " + setting + " --b solver=pgs");
            EXPECT_EQ(r.exitCode, 2) << r.output;
            EXPECT_NE(r.output.find("rubble: --a " + setting + ": " + c.message + "\n"),
                      std::string::npos)
                << r.output;
        }
    }
}

TEST(OptionTable, AVectorComponentIsCheckedAsAFloatAndNamed) {
    const Option& gravity = *findOptionByKey("gravity");
    SimulationOptions sim;
    const Status s = assignOptionText(gravity, "0,1e60,0", "here", OptionTarget{&sim});
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().describe(), "here[1]: is too large for single precision, got 1e+60");
    const Result<Scene> scene =
        parseScene(sceneWith("gravity", "[0, 1e60, 0]"), "inline.json", ".");
    ASSERT_FALSE(scene.ok());
    EXPECT_EQ(scene.error().describe(),
              "inline.json: simulation.gravity[1]: is too large for single precision, got 1e+60");
    EXPECT_FALSE(assignOptionText(gravity, "0,1", "here", OptionTarget{&sim}).ok());
    EXPECT_FALSE(assignOptionText(gravity, "0,1,2,3", "here", OptionTarget{&sim}).ok());
    EXPECT_EQ(sim.gravity, SimulationOptions{}.gravity); // refused values leave the member alone
}

TEST(OptionTable, TextThatIsNotOfTheKindIsRefused) {
    SimulationOptions sim;
    RunOptions run;
    const OptionTarget t{&sim, &run};
    EXPECT_EQ(assignOptionText(*findOptionByKey("dt"), "fast", "w", t).error().message,
              "expected a number, got \"fast\"");
    EXPECT_EQ(assignOptionText(*findOptionByKey("steps"), "1e3", "w", t).error().message,
              "expected an integer, got \"1e3\"");
    EXPECT_EQ(assignOptionText(*findOptionByKey("steps"), "", "w", t).error().message,
              "expected an integer, got \"\"");
    EXPECT_EQ(assignOptionText(*findOptionByName("deterministic"), "maybe", "w", t).error().message,
              "expected true or false, got \"maybe\"");
    EXPECT_TRUE(assignOptionText(*findOptionByName("deterministic"), "yes", "w", t).ok());
    EXPECT_TRUE(run.deterministic);
    EXPECT_EQ(sim.dt, SimulationOptions{}.dt);
    EXPECT_EQ(sim.steps, SimulationOptions{}.steps);
}

TEST(OptionTable, DocsTableIsTheTables) {
    const std::string doc =
        test::readText(std::string(RUBBLE_SOURCE_DIR) + "/docs/scene-format.md");
    const std::string table = simulationOptionsMarkdown();
    EXPECT_NE(doc.find(table), std::string::npos)
        << "docs/scene-format.md's `simulation` table differs from the option table; it should "
           "read:\n"
        << table;
}

TEST(OptionTable, RunHelpIsTheTables) {
    const test::CommandResult r = test::runRubble("run --help");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const Option& o : optionTable()) {
        if (!(o.uses & kUseFlag)) continue;
        const std::string flag = "--" + std::string(o.name) + " " + optionTypeName(o);
        EXPECT_NE(r.output.find(flag), std::string::npos) << flag << " in\n" << r.output;
        EXPECT_NE(r.output.find(optionFlagHelp(o)), std::string::npos)
            << optionFlagHelp(o) << " in\n" << r.output;
    }
}

} // namespace
} // namespace rubble
