// tests/support/stage_input.h: a scene's bodies as the input of single stages (CPU and device
// twins, stage tests and benchmarks): shapes built, body arrays, surfaces, joined pairs; and a
// world's current state taken into them through the world's public queries.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "host/collision/collision_stage.h"
#include "host/core/bodies.h"
#include "host/core/math.h"
#include "host/core/step_params.h"
#include "host/dynamics/joints.h"
#include "host/world/world_build.h"
#include "rubble/world.h"

namespace rubble::test {

/// Stops the program with the error: a stage input that cannot be built is a broken test.
inline void abortOn(const Error& e) {
    std::fprintf(stderr, "stage input: %s\n", e.describe().c_str());
    std::abort();
}

/// What the stages read of a scene, built as World::create builds it.
struct StageInput {
    Scene scene;
    std::vector<Shape> shapes;
    std::vector<std::string> names;
    BodyArrays bodies;
    std::vector<shared::float4> surfaces;
    std::vector<BodyPair> joined;

    CollisionScene collisionScene() const { return {shapes, scene.materials, joined}; }
    /// The step parameters of the scene's options, after `stepsTaken` steps.
    StepParams params(std::int64_t stepsTaken = 0) const {
        return makeStepParams(scene.simulation, stepsTaken);
    }
};

/// The stage input of a parsed scene at its initial state; aborts when a shape does not build.
inline StageInput stageInput(const Scene& scene) {
    StageInput in;
    in.scene = scene;
    for (const ShapeDesc& d : scene.shapes) {
        Result<Shape> shape = buildShape(d);
        if (!shape) abortOn(shape.error());
        in.shapes.push_back(std::move(*shape));
    }
    for (const BodyDesc& b : scene.bodies) {
        appendBodyArrays(in.bodies, b, in.shapes[b.shape]);
        in.names.push_back(b.name);
    }
    in.surfaces = bodySurfaces(scene.materials, in.bodies.materialOf);
    in.joined = joinedPairs(scene.joints);
    return in;
}

/// The same from scene JSON text.
inline StageInput stageInput(const std::string& json) {
    Result<Scene> scene = parseScene(json, "inline.json", ".");
    if (!scene) abortOn(scene.error());
    return stageInput(*scene);
}

/// Takes a world's current state (poses, velocities, momenta, sleep) into the input, through
/// World::body; the world must have been built from the same scene.
inline void takeState(const World& world, StageInput& in) {
    if (world.bodyCount() != in.bodies.count())
        abortOn(makeError(ErrorKind::Internal, "takeState", "the world has other bodies"));
    for (std::uint32_t i = 0; i < world.bodyCount(); ++i) {
        const BodyState b = world.body(i);
        in.bodies.poses[i] = shared::BodyPose{toFloat4(b.position), toFloat4(b.orientation)};
        in.bodies.velocities[i] =
            shared::BodyVelocity{toFloat4(b.linearVelocity), toFloat4(b.angularVelocity)};
        in.bodies.momenta[i] =
            shared::BodyMomentum{toFloat4(b.linearMomentum), toFloat4(b.angularMomentum)};
        std::uint32_t& flags = in.bodies.masses[i].flags;
        flags = b.asleep ? (flags | RUBBLE_BODY_ASLEEP) : (flags & ~RUBBLE_BODY_ASLEEP);
    }
}

} // namespace rubble::test
