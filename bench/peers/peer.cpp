// bench/peers/peer.cpp: runs a peer engine on a rubble scene and writes rubble's file formats.
#include "peer.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "host/io/metrics.h"

namespace rubble::peers {

double bodyMass(const BodyDesc& body, const Shape& shape) {
    if (body.isStatic) return 0.0;
    return body.mass ? double(*body.mass) : double(*body.density) * shape.unitMass.volume;
}

int runPeer(int argc, char** argv, const std::string& engine, const std::string& version,
            const PeerFactory& factory, const PeerOptions& options) {
    CLI::App app{"Runs a rubble scene on " + engine + " for the benchmarks"};
    std::string scenePath, out, metrics;
    std::optional<int> steps;
    int every = 1;
    app.add_option("scene", scenePath, "Scene file")->required();
    app.add_option("--steps", steps, "Steps (default: the scene's)");
    app.add_option("--out", out, "Trajectory, .csv or .jsonl");
    app.add_option("--every", every, "Write every K-th step");
    app.add_option("--metrics", metrics, "Summary, .json");
    if (options) options(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    auto fail = [](const Error& e) {
        std::fprintf(stderr, "%s\n", e.describe().c_str());
        return e.kind == ErrorKind::BadInput || e.kind == ErrorKind::NotSupported ? 2 : 1;
    };
    Result<Scene> scene = loadScene(scenePath);
    if (!scene) return fail(scene.error());
    if (steps) scene->simulation.steps = *steps;
    std::vector<Shape> shapes;
    for (const ShapeDesc& d : scene->shapes) {
        Result<Shape> s = buildShape(d);
        if (!s) return fail(s.error());
        shapes.push_back(std::move(*s));
    }
    Result<std::unique_ptr<PeerWorld>> world = factory(*scene, shapes);
    if (!world) return fail(world.error());
    PeerWorld& w = **world;

    std::optional<TrajectoryWriter> writer;
    std::vector<TrajectoryRow> rows;
    const double dt = scene->simulation.dt;
    if (!out.empty()) {
        Result<TrajectoryWriter> opened = TrajectoryWriter::open(out);
        if (!opened) return fail(opened.error());
        writer.emplace(std::move(*opened));
        w.read(rows);
        if (Status s = writer->write(0, 0.0, rows); !s) return fail(s.error());
    }
    // End-state assessment, as `rubble run --metrics` does it: drift over the last second.
    std::vector<ShapeGeometry> geometry;
    for (const Shape& s : shapes) geometry.push_back(geometryOf(s));
    std::vector<QualityBody> quality(scene->bodies.size());
    for (std::size_t i = 0; i < quality.size(); ++i) {
        const BodyDesc& d = scene->bodies[i];
        const Shape& s = shapes[d.shape];
        quality[i] = QualityBody{&geometry[d.shape], bodyMass(d, s),
                                 s.unitMass.inertia * (bodyMass(d, s) / s.unitMass.volume),
                                 d.isStatic};
        if (d.isStatic) quality[i].inertia = glm::dmat3(0.0);
    }
    const int total = scene->simulation.steps;
    const int driftFrom = std::max(0, total - int(std::lround(1.0 / dt)));
    std::vector<TrajectoryRow> before;
    if (driftFrom == 0) w.read(before);
    std::vector<double> stepMs;
    stepMs.reserve(std::size_t(scene->simulation.steps));
    for (int i = 1; i <= scene->simulation.steps; ++i) {
        const auto start = std::chrono::steady_clock::now();
        w.step();
        stepMs.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        if (i == driftFrom) w.read(before);
        if (writer && i % every == 0) {
            w.read(rows);
            if (Status s = writer->write(i, i * dt, rows); !s) return fail(s.error());
        }
    }
    if (writer)
        if (Status s = writer->finish(); !s) return fail(s.error());
    double wall = 0.0;
    for (double ms : stepMs) wall += ms / 1000.0;
    if (!metrics.empty()) {
        nlohmann::ordered_json j;
        j["scene"] = scene->name;
        j["steps"] = stepMs.size();
        j["bodies"] = scene->bodies.size();
        j["wall_s"] = wall;
        j["ms_per_step"] = {{"median", percentile(stepMs, 0.5)}, {"p90", percentile(stepMs, 0.9)}};
        w.read(rows);
        j["quality"] = qualityJson(assessQuality(quality, rows, before, (total - driftFrom) * dt));
        if (const std::optional<std::size_t> asleep = w.asleep()) j["asleep"] = {{"last", *asleep}};
        j["engine"] = engine;
        j["engine_version"] = version;
        if (const std::string device = w.device(); !device.empty()) j["device"] = device;
        j["caveats"] = w.caveats();
        if (Status s = writeFileAtomically(metrics, j.dump(2) + "\n"); !s) return fail(s.error());
    }
    std::printf("%s on %s: %zu steps, %zu bodies, %.3f ms/step (median)\n", engine.c_str(),
                scene->name.c_str(), stepMs.size(), scene->bodies.size(), percentile(stepMs, 0.5));
    return 0;
}

} // namespace rubble::peers
