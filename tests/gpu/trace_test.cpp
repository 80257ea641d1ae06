// tests/gpu/trace_test.cpp: `rubble run --trace` writes the device's commands of every step as
// Chrome trace events that agree with the metrics' kernel totals, in queue order, with the
// host's steps placed on the device's clock.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "gpu_fixture.h"

namespace rubble {
namespace {

// Nanoseconds from the trace's microseconds (written to the nanosecond).
std::int64_t ns(const nlohmann::json& us) { return std::llround(us.get<double>() * 1000.0); }

class Trace : public test::GpuTest {
  protected:
    // stack_10 with SAT and PGS on the device: contacts from the first step, so that the
    // coloring's reads and the colored sweeps are in every step.
    static constexpr int kSteps = 6;
    void runTraced() {
        dir_ = test::tempDir("trace");
        const test::CommandResult r = test::runRubble(
            "run " + std::string(RUBBLE_SOURCE_DIR) + "/scenes/stack_10.json --steps " +
            std::to_string(kSteps) + " --backend opencl --collision sat --quiet --trace " + dir_ +
            "/t.json --metrics " + dir_ + "/m.json");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        trace_ = nlohmann::json::parse(test::readText(dir_ + "/t.json"));
        metrics_ = nlohmann::json::parse(test::readText(dir_ + "/m.json"));
        for (const nlohmann::json& e : trace_.at("traceEvents")) {
            if (e.at("ph") != "X") continue;
            (e.at("tid") == 1 ? device_ : host_).push_back(e);
        }
    }
    std::string dir_;
    nlohmann::json trace_, metrics_;
    std::vector<nlohmann::json> device_, host_;
};

TEST_F(Trace, CommandsRunInQueueOrderStepByStepWithoutOverlap) {
    runTraced();
    ASSERT_FALSE(device_.empty());
    std::set<std::string> stages;
    for (const auto& [stage, ms] : metrics_.at("device_stages_ms").items()) stages.insert(stage);
    std::int64_t step = 0, previousEnd = 0;
    std::set<std::int64_t> seen;
    for (const nlohmann::json& e : device_) {
        for (const char* key : {"name", "cat", "ts", "dur", "pid", "tid", "args"})
            ASSERT_TRUE(e.contains(key)) << key << " missing in " << e.dump();
        EXPECT_TRUE(stages.count(e.at("cat").get<std::string>())) << e.dump();
        const std::int64_t s = e.at("args").at("step").get<std::int64_t>();
        ASSERT_GE(s, step) << "steps out of order at " << e.dump();
        step = s;
        seen.insert(s);
        // The in-order queue: each command starts once the one before it has ended.
        const std::int64_t start = ns(e.at("ts")), end = start + ns(e.at("dur"));
        EXPECT_GE(start, previousEnd) << e.dump();
        EXPECT_GE(end, start);
        previousEnd = end;
        EXPECT_GE(e.at("args").at("queued_to_start_us").get<double>(),
                  e.at("args").at("submit_to_start_us").get<double>());
        EXPECT_GE(e.at("args").at("submit_to_start_us").get<double>(), 0.0);
    }
    EXPECT_EQ(seen.size(), std::size_t(kSteps));
    EXPECT_EQ(*seen.begin(), 1);
}

TEST_F(Trace, EveryKernelOfTheMetricsWithItsLaunchesAndTime) {
    runTraced();
    struct Sum {
        std::int64_t launches = 0, ns = 0;
    };
    std::map<std::string, Sum> traced;
    for (const nlohmann::json& e : device_) {
        Sum& s = traced[e.at("name").get<std::string>()];
        s.launches += 1;
        s.ns += ns(e.at("dur"));
    }
    const nlohmann::json& kernels = metrics_.at("device_kernels");
    ASSERT_EQ(traced.size(), kernels.size());
    for (const nlohmann::json& k : kernels) {
        const std::string name = k.at("name").get<std::string>();
        ASSERT_TRUE(traced.count(name)) << name << " is in the metrics, not in the trace";
        const Sum& s = traced[name];
        EXPECT_EQ(s.launches, k.at("launches").get<std::int64_t>()) << name;
        // The trace's durations are whole nanoseconds, as the profiling times are.
        EXPECT_NEAR(double(s.ns) * 1e-6, k.at("ms").get<double>(), 1e-9 * double(s.launches) + 1e-9)
            << name;
    }
    EXPECT_GT(traced["solvePgs"].launches, kSteps);
}

// The host waits in the middle of a SAT step: it reads the status block, then the pair summaries
// and the pairs, colors them and only then enqueues the rows. Those reads are the device's work
// and are in the trace, so that the gap before the rows is the host's coloring alone.
TEST_F(Trace, TheReadsBeforeTheColoringAreInTheTrace) {
    runTraced();
    std::map<std::int64_t, std::vector<std::string>> names;
    for (const nlohmann::json& e : device_)
        names[e.at("args").at("step").get<std::int64_t>()].push_back(e.at("name"));
    for (const auto& [step, list] : names) {
        const auto rows = std::find(list.begin(), list.end(), "buildPgsRows");
        ASSERT_NE(rows, list.end()) << "step " << step;
        const auto summaries =
            std::find(std::make_reverse_iterator(rows), list.rend(), std::string("summarizePairs"));
        ASSERT_NE(summaries, list.rend()) << "step " << step;
        EXPECT_EQ(std::count(summaries.base(), rows, "(read from device)"), 3) << "step " << step;
    }
}

TEST_F(Trace, HostStepsHoldTheEnqueueOfTheirCommands) {
    runTraced();
    ASSERT_EQ(host_.size(), std::size_t(kSteps));
    std::map<std::int64_t, std::pair<std::int64_t, std::int64_t>> span;
    std::int64_t previousEnd = std::numeric_limits<std::int64_t>::min();
    for (const nlohmann::json& h : host_) {
        const std::int64_t begin = ns(h.at("ts")), end = begin + ns(h.at("dur"));
        EXPECT_GE(begin, previousEnd) << h.dump();
        previousEnd = end;
        span[h.at("args").at("step").get<std::int64_t>()] = {begin, end};
    }
    // Every command is enqueued inside World::step: its QUEUED time, carried to the host's clock,
    // lies in its step's span. A clock relation off by more than the slack (50 us, against the
    // few microseconds an enqueue takes) fails this.
    const std::int64_t slack = 50'000;
    for (const nlohmann::json& e : device_) {
        const std::int64_t queued = ns(e.at("ts")) - ns(e.at("args").at("queued_to_start_us"));
        const auto [begin, end] = span.at(e.at("args").at("step").get<std::int64_t>());
        EXPECT_GE(queued, begin - slack) << e.dump();
        EXPECT_LE(queued, end + slack) << e.dump();
    }
    EXPECT_NE(trace_.at("otherData").at("clock").get<std::string>().find("device clock"),
              std::string::npos);
}

// The trace ends with the device's buffers, each named by the call in host/gpu that made it:
// the SAT path's pair sets among them, and their peak at least what is held at the end.
TEST_F(Trace, ListsTheDeviceBuffersByTheCallThatMadeThem) {
    runTraced();
    const auto& other = trace_.at("otherData");
    const std::string buffers = other.at("device_buffers").get<std::string>();
    EXPECT_NE(buffers.find("pairs.cpp:"), std::string::npos) << buffers;
    EXPECT_NE(buffers.find("device_bodies.cpp:"), std::string::npos) << buffers;
    double held = 0;
    for (std::size_t at = buffers.find(" MiB"); at != std::string::npos;
         at = buffers.find(" MiB", at + 1))
        held += std::stod(buffers.substr(buffers.rfind(' ', at - 1) + 1));
    const std::string peak = other.at("device_buffers_peak").get<std::string>();
    EXPECT_GT(held, 0.0);
    // Each size is rounded to 0.001 MiB in the listing.
    EXPECT_GE(std::stod(peak) +
                  0.0005 * double(std::count(buffers.begin(), buffers.end(), ',') + 2),
              held)
        << peak << " | " << buffers;
}

TEST_F(Trace, AFolderThatCannotBeWrittenNamesTheOption) {
    const std::string dir = test::tempDir("trace_bad");
    const test::CommandResult r = test::runRubble(
        "run " + std::string(RUBBLE_SOURCE_DIR) +
        "/scenes/stack_10.json --steps 2 --backend opencl --collision sat --quiet --trace " + dir +
        "/missing/t.json");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("--trace"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(dir + "/missing/t.json"), std::string::npos) << r.output;
}

TEST_F(Trace, TheWorldGivesItsLastStepsCommandsInTimeOrder) {
    Result<Scene> scene = loadScene(std::string(RUBBLE_SOURCE_DIR) + "/scenes/stack_10.json");
    ASSERT_TRUE(scene.ok()) << scene.error().describe();
    scene->simulation.backend = Backend::OpenCl;
    scene->simulation.collision.method = CollisionMethod::Sat;
    RunOptions run;
    run.context = context();
    Result<World> made = World::create(*scene, run);
    ASSERT_TRUE(made.ok()) << made.error().describe();
    World& w = *made;
    // Not kept unless asked.
    ASSERT_TRUE(w.step().ok());
    EXPECT_TRUE(w.lastDeviceCommands().empty());
    w.keepDeviceCommands(true);
    Result<DeviceClockSample> before = w.sampleDeviceClock();
    ASSERT_TRUE(before.ok()) << before.error().describe();
    EXPECT_LE(before->hostBeforeNs, before->hostAfterNs);
    ASSERT_TRUE(w.step().ok());
    const std::span<const DeviceCommand> commands = w.lastDeviceCommands();
    ASSERT_FALSE(commands.empty());
    for (const DeviceCommand& c : commands) {
        EXPECT_LE(c.queuedNs, c.submitNs) << c.name;
        EXPECT_LE(c.submitNs, c.startNs) << c.name;
        EXPECT_LE(c.startNs, c.endNs) << c.name;
        // The step's commands were enqueued after the sample's marker.
        EXPECT_GE(c.queuedNs, before->deviceNs) << c.name;
    }
    double busyNs = 0;
    for (const DeviceCommand& c : commands) busyNs += double(c.endNs - c.startNs);
    EXPECT_NEAR(busyNs * 1e-6, w.lastStep().deviceMs, 1e-9 * double(commands.size()));
}

} // namespace
} // namespace rubble
