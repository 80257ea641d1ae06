// host/world/world_build.cpp: a Scene into a WorldState: shapes built, masses from mass or
// density, momenta from the initial velocities. Combinations that cannot run are refused here.
#include "host/world/world_build.h"

#include "host/core/mass_properties.h"
#include "host/core/math.h"
#include "host/core/step_params.h"
#include "host/dynamics/joints.h"
#include "host/gpu/context.h"
#include "host/world/backend_check.h"
#include "host/world/device_step.h"
#include "host/world/world_state.h"
#include <cstdio>

namespace rubble {
namespace {

// Lemke's method solves the frictionless contact LCP: two bodies, one of them dynamic, whose
// materials both have friction would make a contact with friction sqrt(mu_a mu_b) > 0.
Status checkLemkeFrictionless(const Scene& scene) {
    if (scene.simulation.solverType() != SolverType::Lemke) return {};
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

// Kinematic bodies move on the SAT pipelines (the CPU's and the device's) with PGS only: the
// particle path places the particles of a body that does not integrate once, at load, and only
// PGS's rows give a turning body of infinite mass its arms (rubble/shared/pgs_row.h).
Status checkKinematic(const Scene& scene) {
    for (const BodyDesc& b : scene.bodies) {
        if (!b.isKinematic) continue;
        if (scene.simulation.collisionMethod() == CollisionMethod::Particles)
            return makeError(ErrorKind::NotSupported, b.where + ".kinematic",
                             "kinematic body \"" + b.name +
                                 "\": particle collision places the particles of bodies "
                                 "that do not integrate once; collide with sat (--collision sat)");
        if (scene.simulation.solverType() != SolverType::Pgs)
            return makeError(ErrorKind::NotSupported, b.where + ".kinematic",
                             "kinematic body \"" + b.name + "\": the " +
                                 std::string(toString(scene.simulation.solverType())) +
                                 " solver's rows do not see a turning wall; solve with pgs "
                                 "(--solver pgs)");
    }
    return {};
}

// The device collides capsules with SAT only: its particle path has no capsule particles.
Status checkCapsules(const Scene& scene) {
    const bool deviceParticles = scene.simulation.backend == Backend::OpenCl &&
                                 scene.simulation.collisionMethod() == CollisionMethod::Particles;
    if (!deviceParticles) return {};
    for (const BodyDesc& b : scene.bodies) {
        const ShapeDesc& shape = scene.shapes[b.shape];
        if (shape.type != ShapeType::Capsule) continue;
        return makeError(ErrorKind::NotSupported, b.where + ".shape",
                         "body \"" + b.name + "\" is a capsule (shape \"" + shape.name + "\"): " +
                             "the opencl backend collides capsules with sat only; collide "
                             "with sat (--collision sat) or run on the cpu backend "
                             "(--backend cpu)");
    }
    return {};
}

// Static meshes and height fields collide by their triangles in the SAT narrow phase (both
// pipelines); particles would voxelise the level as a closed solid.
Status checkLevelMeshes(const Scene& scene) {
    if (scene.simulation.collisionMethod() != CollisionMethod::Particles) return {};
    for (const BodyDesc& b : scene.bodies) {
        const ShapeDesc& shape = scene.shapes[b.shape];
        if (!b.isStatic || shape.type != ShapeType::Mesh) continue;
        const std::string kind = shape.heightField ? "heightfield" : "static triangle mesh";
        return makeError(ErrorKind::NotSupported, b.where + ".shape",
                         "body \"" + b.name + "\" is a " + kind + " (shape \"" + shape.name +
                             "\"): particle collision does not collide with level triangles; "
                             "collide with sat (--collision sat)");
    }
    return {};
}

// Turning continuous collision off is the CPU's SAT path's choice: the device's SAT always widens
// its margins, and particles have none to widen.
Status checkContinuous(const Scene& scene) {
    const SimulationOptions& sim = scene.simulation;
    if (sim.continuous) return {};
    if (sim.backend == Backend::OpenCl || sim.collisionMethod() == CollisionMethod::Particles)
        return makeError(ErrorKind::NotSupported, scene.file + ": simulation.continuous",
                         "continuous collision can be turned off on the cpu backend with sat "
                         "collision only (the device's sat always widens its contact margins; "
                         "particles have none to widen)");
    return {};
}

// Contact recycling is the CPU's SAT path's: the device's SAT collides every pair every step.
Status checkRecycling(const Scene& scene) {
    const SimulationOptions& sim = scene.simulation;
    if (!sim.collision.recycleContacts) return {};
    if (sim.backend == Backend::OpenCl || sim.collisionMethod() == CollisionMethod::Particles)
        return makeError(ErrorKind::NotSupported,
                         scene.file + ": simulation.collision.recycle_contacts",
                         "contact recycling runs on the cpu backend with sat collision only (the "
                         "device's sat collides every pair every step; particles have no "
                         "manifolds)");
    return {};
}

// Refuses options and scene parts that the pipeline cannot run, naming the field.
Status checkSupported(const Scene& scene) {
    RUBBLE_TRY(checkBackendCombination(scene));
    RUBBLE_TRY(checkKinematic(scene));
    RUBBLE_TRY(checkCapsules(scene));
    RUBBLE_TRY(checkLevelMeshes(scene));
    RUBBLE_TRY(checkContinuous(scene));
    RUBBLE_TRY(checkRecycling(scene));
    RUBBLE_TRY(checkLemkeFrictionless(scene));
    return {};
}

BodyMass makeMass(const BodyDesc& b, const Shape& shape) {
    BodyMass m{};
    if (b.isStatic) {
        m.flags = RUBBLE_BODY_STATIC;
        return m;
    }
    // Infinite mass, as a static body; its velocities are its own (integratePositions).
    if (b.isKinematic) {
        m.flags = RUBBLE_BODY_KINEMATIC;
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

std::string massText(float kg) {
    char text[32];
    std::snprintf(text, sizeof text, "%g kg", double(kg));
    return text;
}

// The lightest and the heaviest dynamic bodies, when they differ more than kStackMassRatio
// times: stacks past that ratio may sink or tip (docs/dynamics.md, "Mass ratios").
std::optional<Warning> massRatioWarning(const Scene& scene, const BodyArrays& bodies) {
    std::optional<std::uint32_t> light, heavy;
    for (std::uint32_t i = 0; i < bodies.count(); ++i) {
        if (bodies.isStatic(i)) continue;
        const float m = bodies.masses[i].mass;
        if (!light || m < bodies.masses[*light].mass) light = i;
        if (!heavy || m > bodies.masses[*heavy].mass) heavy = i;
    }
    if (!light) return std::nullopt;
    const float lightKg = bodies.masses[*light].mass, heavyKg = bodies.masses[*heavy].mass;
    if (double(heavyKg) <= double(kStackMassRatio) * double(lightKg)) return std::nullopt;
    const BodyDesc& l = scene.bodies[*light];
    const BodyDesc& h = scene.bodies[*heavy];
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "1:%.3g", double(heavyKg) / double(lightKg));
    // A body's where is `file: bodies[3]` (or a generator's): the file once, then both fields.
    auto field = [](const std::string& where) {
        const std::size_t colon = where.find(": ");
        return colon == std::string::npos ? where : where.substr(colon + 2);
    };
    return Warning{scene.file + ": " + field(l.where) + " and " + field(h.where),
                   "the masses of dynamic bodies " + l.name + " (" + massText(lightKg) + ") and " +
                       h.name + " (" + massText(heavyKg) + ") differ " + ratio +
                       "; stacks stand up to 1:" + std::to_string(int(kStackMassRatio)) +
                       ", past it a heavy body on a light one may sink or tip (docs/dynamics.md, "
                       "mass ratios)"};
}

} // namespace

BodyMomentum momentumFromVelocity(const BodyMass& mass, const BodyPose& pose, glm::vec3 linear,
                                  glm::vec3 angular) {
    const Mat3 inertiaWorld =
        shared::mat3RotateTensor(shared::mat3FromQuat(pose.orientation), mass.inertiaBody);
    BodyMomentum momentum{};
    momentum.linear = toFloat4(linear * mass.mass);
    momentum.angular = shared::mat3MulVec(inertiaWorld, toFloat4(angular));
    return momentum;
}

void appendBodyArrays(BodyArrays& a, const BodyDesc& b, const Shape& shape) {
    const BodyMass mass = makeMass(b, shape);
    const BodyPose pose{toFloat4(b.position), toFloat4(glm::normalize(b.orientation))};
    const BodyMomentum momentum =
        momentumFromVelocity(mass, pose, b.linearVelocity, b.angularVelocity);
    a.poses.push_back(pose);
    a.masses.push_back(mass);
    a.momenta.push_back(momentum);
    // A kinematic body has no momenta: its velocities are the state.
    a.velocities.push_back(
        b.isKinematic ? BodyVelocity{toFloat4(b.linearVelocity), toFloat4(b.angularVelocity)}
                      : shared::velocityFromMomentumItem(momentum, mass, pose.orientation));
    a.forces.push_back(BodyForce{});
    a.shapeOf.push_back(b.shape);
    a.materialOf.push_back(b.material);
}

void appendBody(WorldState& s, const BodyDesc& b) {
    appendBodyArrays(s.bodies, b, s.shapes[b.shape]);
    s.names.push_back(b.name);
    const MaterialDesc& m = s.materials[b.material];
    s.surfaces.push_back(shared::vec4(m.friction, m.restitution, 0.0f));
    s.debris.push_back(b.debris ? 1 : 0);
    s.velocitiesBeforeSolve.emplace_back();
    s.velocitiesAtStart.emplace_back();
}

Result<World> World::create(const Scene& scene, const RunOptions& run) {
    RUBBLE_TRY(checkSupported(scene));
    auto s = std::make_unique<WorldState>();
    s->sceneName = scene.name;
    s->options = scene.simulation;
    // The options in effect: what the scene leaves out is its backend's default.
    s->options.collision.method = scene.simulation.collisionMethod();
    s->options.solver.type = scene.simulation.solverType();
    s->run = run;
    s->materials = scene.materials;
    // A mesh on a static body collides by its triangles; on a moving one, by its hull.
    std::vector<ShapeUse> uses(scene.shapes.size(), ShapeUse{false, false});
    for (const BodyDesc& b : scene.bodies) {
        uses[b.shape].level = uses[b.shape].level || b.isStatic;
        uses[b.shape].moving = uses[b.shape].moving || !b.isStatic;
    }
    for (std::size_t i = 0; i < scene.shapes.size(); ++i) {
        const ShapeDesc& d = scene.shapes[i];
        Result<Shape> shape = buildShape(d, uses[i]);
        RUBBLE_TRY(shape);
        s->geometry.push_back(geometryOf(*shape));
        s->shapes.push_back(std::move(*shape));
    }
    const std::size_t n = scene.bodies.size();
    s->names.reserve(n);
    s->bodies.poses.reserve(n);
    s->bodies.momenta.reserve(n);
    s->bodies.masses.reserve(n);
    for (const BodyDesc& b : scene.bodies) {
        appendBody(*s, b);
        if (!b.isStatic && !b.isKinematic)
            RUBBLE_TRY(checkMassRange(s->bodies.masses.back(), b.where,
                                      b.mass ? "mass" : "density"));
    }
    if (std::optional<Warning> w = massRatioWarning(scene, s->bodies)) s->warnings.push_back(*w);
    s->joints = scene.joints;
    s->joined = joinedPairs(s->joints);
    s->events = scene.events;
    s->eventFired.assign(scene.events.size(), 0);
    if (scene.simulation.backend == Backend::OpenCl) {
        // Bodies the device does not step (joints, outside the debris set) get a CPU world.
        std::shared_ptr<gpu::Context> context = run.context;
        if (!context) {
            Result<std::shared_ptr<gpu::Context>> opened = gpu::Context::create(run);
            RUBBLE_TRY(opened);
            context = std::move(*opened);
        }
        RUBBLE_TRY(attachScene(*s, scene, std::move(context), run));
        return World(std::move(s));
    }
    // The CPU pipeline's stages, chosen here once: the solver, and the collision method that
    // delivers the contacts in the form the solver reads.
    s->solver = makeContactSolver(scene.simulation.solverType());
    s->collision = makeCollisionStage(scene.simulation.collisionMethod(), s->solver->reads());
    RUBBLE_TRY(s->collision->rebuild(s->collisionScene(), s->bodies.view(),
                                     scene.simulation.collision.particleSpacing));
    return World(std::move(s));
}

Result<std::shared_ptr<gpu::Context>> openDevice(const RunOptions& run) {
    return gpu::Context::create(run);
}

} // namespace rubble
