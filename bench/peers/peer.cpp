// bench/peers/peer.cpp: runs a peer engine on a rubble scene and writes rubble's file formats.
#include "peer.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "host/io/metrics.h"
#include "rubble/shared/events.h"

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
    // As the world builds them: a mesh on a static body also gets its triangles (a peer that
    // has triangle meshes collides with those), on a moving one its hull.
    std::vector<ShapeUse> uses(scene->shapes.size(), ShapeUse{false, false});
    for (const BodyDesc& b : scene->bodies) {
        uses[b.shape].level = uses[b.shape].level || b.isStatic;
        uses[b.shape].moving = uses[b.shape].moving || !b.isStatic;
    }
    std::vector<Shape> shapes;
    for (std::size_t i = 0; i < scene->shapes.size(); ++i) {
        const ShapeDesc& d = scene->shapes[i];
        Result<Shape> s = buildShape(d, uses[i]);
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
    // The scene's explosions, as rubble's applyForces: at the start of the first step whose time
    // reaches theirs, each dynamic body within reach gets its impulse (rubble/shared/events.h).
    std::vector<std::uint8_t> fired(scene->events.size(), 0);
    std::vector<TrajectoryRow> at;
    bool explosionsApplied = true;
    for (int i = 1; i <= scene->simulation.steps; ++i) {
        const double time = (i - 1) * dt;
        for (std::size_t e = 0; e < scene->events.size(); ++e) {
            const EventDesc& x = scene->events[e];
            if (fired[e] || !(time + 1e-9 >= double(x.time))) continue;
            fired[e] = 1;
            w.read(at);
            const shared::float4 centre{x.centre.x, x.centre.y, x.centre.z, 0.0f};
            for (std::size_t b = 0; b < scene->bodies.size(); ++b) {
                const BodyDesc& d = scene->bodies[b];
                if (d.isStatic || d.isKinematic) continue;
                const glm::vec3 p = at[b].position;
                const shared::float4 j = shared::explosionImpulseItem(
                    shared::float4{p.x, p.y, p.z, 0.0f}, centre, x.impulse, x.radius);
                if (j.w == 0.0f) continue;
                explosionsApplied = w.applyImpulse(b, glm::vec3(j.x, j.y, j.z)) && explosionsApplied;
            }
        }
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
        std::vector<std::string> caveats = w.caveats();
        if (!explosionsApplied)
            caveats.push_back("the scene's explosions are not applied (the runner has no impulses)");
        j["caveats"] = caveats;
        if (Status s = writeFileAtomically(metrics, j.dump(2) + "\n"); !s) return fail(s.error());
    }
    std::printf("%s on %s: %zu steps, %zu bodies, %.3f ms/step (median)\n", engine.c_str(),
                scene->name.c_str(), stepMs.size(), scene->bodies.size(), percentile(stepMs, 0.5));
    return 0;
}

} // namespace rubble::peers
