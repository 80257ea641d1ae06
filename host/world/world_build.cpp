// host/world/world_build.cpp: a Scene into a WorldState: shapes built, masses from mass or
// density, momenta from the initial velocities. Combinations that cannot run are refused here.
#include "host/world/world_build.h"
#include "host/core/mass_properties.h"
#include "host/core/math.h"
#include "host/dynamics/joints.h"
#include "host/gpu/context.h"
#include "host/world/backend_check.h"
#include "host/world/device_step.h"
#include "host/world/world_state.h"

namespace rubble {
namespace {

// Lemke's method solves the frictionless contact LCP: two bodies, one of them dynamic, whose
// materials both have friction would make a contact with friction sqrt(mu_a mu_b) > 0.
Status checkLemkeFrictionless(const Scene& scene) {
    if (scene.simulation.solver.type != SolverType::Lemke) return {};
    std::size_t rough = 0;
    std::optional<std::uint32_t> roughDynamic;
    for (const BodyDesc& b : scene.bodies) {
        if (scene.materials[b.material].friction <= 0.0f) continue;
        ++rough;
        if (!b.isStatic && !roughDynamic) roughDynamic = b.material;
    }
    if (rough < 2 || !roughDynamic) return {};
    const MaterialDesc& m = scene.materials[*roughDynamic];
    return makeError(ErrorKind::NotSupported, scene.file + ": materials." + m.name + ".friction",
                     "the lemke solver takes frictionless contacts only, and this material has "
                     "friction " +
                         std::to_string(m.friction) +
                         " (set it to 0, or use lcp-jacobi, which bounds friction)");
}

// Refuses options and scene parts that the pipeline cannot run, naming the field.
Status checkSupported(const Scene& scene) {
    RUBBLE_TRY(checkBackendCombination(scene));
    RUBBLE_TRY(checkLemkeFrictionless(scene));
    return {};
}

BodyMass makeMass(const BodyDesc& b, const Shape& shape) {
    BodyMass m{};
    if (b.isStatic) {
        m.flags = RUBBLE_BODY_STATIC;
        return m;
    }
    const double volume = shape.unitMass.volume;
    const double mass = b.mass ? double(*b.mass) : double(*b.density) * volume;
    const glm::mat3 inertia = inertiaForMass(shape.unitMass, mass);
    m.mass = float(mass);
    m.inverseMass = float(1.0 / mass);
    m.inertiaBody = toShared(inertia);
    m.inverseInertiaBody = toShared(glm::inverse(inertia));
    return m;
}

} // namespace

void appendBody(WorldState& s, const BodyDesc& b) {
    const Shape& shape = s.shapes[b.shape];
    const BodyMass mass = makeMass(b, shape);
    const BodyPose pose{toFloat4(b.position), toFloat4(glm::normalize(b.orientation))};
    const Mat3 inertiaWorld =
        shared::mat3RotateTensor(shared::mat3FromQuat(pose.orientation), mass.inertiaBody);
    BodyMomentum momentum{};
    momentum.linear = toFloat4(b.linearVelocity * mass.mass);
    momentum.angular = shared::mat3MulVec(inertiaWorld, toFloat4(b.angularVelocity));
    s.names.push_back(b.name);
    s.poses.push_back(pose);
    s.masses.push_back(mass);
    s.momenta.push_back(momentum);
    s.velocities.push_back(shared::velocityFromMomentumItem(momentum, mass, pose.orientation));
    s.forces.push_back(BodyForce{});
    s.shapeOf.push_back(b.shape);
    s.materialOf.push_back(b.material);
    s.debris.push_back(b.debris ? 1 : 0);
    s.velocitiesBeforeSolve.emplace_back();
    s.velocitiesAtStart.emplace_back();
}

Result<World> World::create(const Scene& scene, const RunOptions& run) {
    RUBBLE_TRY(checkSupported(scene));
    auto s = std::make_unique<WorldState>();
    s->sceneName = scene.name;
    s->options = scene.simulation;
    s->run = run;
    s->materials = scene.materials;
    for (const ShapeDesc& d : scene.shapes) {
        Result<Shape> shape = buildShape(d);
        RUBBLE_TRY(shape);
        s->shapes.push_back(std::move(*shape));
    }
    const std::size_t n = scene.bodies.size();
    s->names.reserve(n);
    s->poses.reserve(n);
    s->momenta.reserve(n);
    s->masses.reserve(n);
    for (const BodyDesc& b : scene.bodies) {
        appendBody(*s, b);
        if (!b.isStatic) RUBBLE_TRY(checkMassRange(s->masses.back(), b.where, b.mass ? "mass" : "density"));
    }
    s->joints = scene.joints;
    s->joined = joinedPairs(s->joints);
    s->events = scene.events;
    s->eventFired.assign(scene.events.size(), 0);
    if (scene.simulation.collisionMethod() == CollisionMethod::Particles)
        RUBBLE_TRY(buildParticles(*s));
    if (scene.simulation.backend == Backend::OpenCl) {
        // Bodies the device does not step (joints, outside the debris set) get a CPU world.
        Result<std::shared_ptr<gpu::Context>> context = gpu::Context::create(run);
        RUBBLE_TRY(context);
        RUBBLE_TRY(attachScene(*s, scene, std::move(*context), run));
    }
    return World(std::move(s));
}

} // namespace rubble
