// tests/gpu/debris_offload_test.cpp: debris offloading on the OpenCL device beside CPU bodies:
// one-way coupling leaves the CPU bodies alone and carries debris on them, two-way coupling
// pushes them and keeps momentum, sleeping debris costs no rows and explosions wake it, and the
// debris flag changes nothing on the cpu backend. Also the explosion kernel, sleeping against
// its CPU twin, and the host API for debris (bulk add, transforms, removal).
#include <cstring>

#include "gpu_fixture.h"
#include "host/core/math.h"
#include "host/dynamics/forces.h"
#include "host/world/backend_check.h"
#include "host/world/offload.h"
#include "rubble/world.h"

namespace rubble {
namespace {

class DebrisOffload : public test::GpuTest {};

// Header and shapes shared by the scenes below: 0.5 m crates (8 particles at 0.25 m).
std::string scene(const std::string& simulation, const std::string& bodies,
                  const std::string& generators, const std::string& extra = "") {
    return R"({"format": "rubble-scene", "version": 1, "name": "offload",
      "simulation": {"dt": 0.016666667, "collision": {"method": "particles",
                     "particle_spacing": 0.25}, "solver": {"type": "jacobi", "iterations": 10})" +
           simulation + R"(},
      "materials": {"default": {"friction": 0.5, "restitution": 0.0},
                    "ice": {"friction": 0.0, "restitution": 0.0}},
      "shapes": {"ground": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.25, 0.25, 0.25]},
                 "block": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                 "slab": {"type": "box", "half_extents": [2, 0.25, 2]}},
      "bodies": [)" +
           bodies + R"(],
      "generators": [)" +
           generators + "]" + extra + "}";
}

const char* kFloor = R"({"name": "floor", "shape": "ground", "static": true})";
const char* kRagdoll = R"({"type": "ragdoll", "name_prefix": "doll", "position": [0, 1.2, 0]})";

// One-way: a ragdoll and a free box under a rain of debris step exactly as in a cpu world
// without the debris (same bits, 120 steps), while the debris lands on them.
TEST_F(DebrisOffload, OneWayLeavesTheCpuBodiesAsTheyWouldBeWithoutDebris) {
    const std::string box = R"(, {"name": "box", "shape": "block", "mass": 4,
                                   "position": [3, 0.5, 0]},
                                 {"name": "lid", "shape": "crate", "mass": 1, "debris": true,
                                  "position": [3, 1.5, 0]})";
    const std::string rain = std::string(kRagdoll) + R"(, {"type": "grid", "shape": "crate",
        "mass": 1, "count": [4, 3, 4], "origin": [-0.9, 2.5, -0.9], "spacing": [0.6, 0.6, 0.6],
        "rotation_jitter": 0.2, "seed": 4, "name_prefix": "d", "debris": true})";
    World offloaded = deviceWorld(scene("", std::string(kFloor) + box, rain));
    ASSERT_FALSE(offloaded.onDevice(*offloaded.findBody("box")));
    ASSERT_TRUE(offloaded.onDevice(*offloaded.findBody("lid")));
    // The same CPU bodies in the same order, without the debris, on the reference pipeline.
    std::string alone = scene("", std::string(kFloor) + R"(, {"name": "box", "shape": "block",
        "mass": 4, "position": [3, 0.5, 0]})",
                              kRagdoll);
    alone.replace(alone.find("\"jacobi\""), 8, "\"pgs\"");
    alone.replace(alone.find("\"particles\""), 11, "\"sat\"");
    World reference = test::worldFromText(alone);
    for (int i = 0; i < 120; ++i) {
        ASSERT_TRUE(offloaded.step().ok()) << "step " << i;
        ASSERT_TRUE(reference.step().ok());
    }
    for (std::uint32_t i = 0; i < reference.bodyCount(); ++i) {
        const std::uint32_t j = *offloaded.findBody(reference.bodyName(i));
        EXPECT_TRUE(test::sameBits(offloaded.body(j), reference.body(i))) << reference.bodyName(i);
    }
    // The lid rests on the box: its centre 0.25 m above the box's top.
    EXPECT_NEAR(offloaded.body(*offloaded.findBody("lid")).position.y, 1.25f, 0.05f);
    EXPECT_GT(offloaded.lastStep().deviceContactCount, 0u);
}

// A crate resting on a slab that the host carries sideways at 1 m/s (its weight held by a
// force): friction takes the crate along, and after 2 s it is still on top, moving with it.
TEST_F(DebrisOffload, DebrisOnAMovingCpuPlatformMovesWithIt) {
    World w = deviceWorld(scene("", R"({"name": "slab", "shape": "slab", "mass": 100,
        "position": [0, 0, 0]}, {"name": "crate", "shape": "crate", "mass": 1, "debris": true,
        "position": [0, 0.5, 0]})",
                                   ""));
    const std::uint32_t slab = *w.findBody("slab"), crate = *w.findBody("crate");
    w.applyImpulse(slab, glm::vec3(100.0f, 0.0f, 0.0f), w.body(slab).position);
    for (int i = 0; i < 120; ++i) {
        w.addForce(slab, glm::vec3(0.0f, 100.0f * 9.81f, 0.0f));
        ASSERT_TRUE(w.step().ok()) << "step " << i;
    }
    const BodyState s = w.body(slab), c = w.body(crate);
    EXPECT_NEAR(s.position.x, 2.0f, 0.02f);
    EXPECT_NEAR(s.position.y, 0.0f, 1e-3f);
    // Slipping while friction caught it up costs at most 0.15 m of the 2 m.
    EXPECT_GT(c.position.x, 1.85f);
    EXPECT_NEAR(c.position.y, 0.5f, 0.05f);
    EXPECT_NEAR(c.linearVelocity.x, 1.0f, 0.05f);
}

// Horizontal momentum of every body, plus what the device gathered and the CPU has not
// applied yet (two-way coupling lags one step).
glm::dvec3 horizontalMomentum(const World& w) {
    glm::dvec3 p(0.0);
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) p += glm::dvec3(w.body(i).linearMomentum);
    p += glm::dvec3(w.pendingCouplingImpulse());
    return glm::dvec3(p.x, 0.0, p.z);
}

std::string stream(const std::string& coupling) {
    return scene(R"(, "coupling": ")" + coupling + "\"",
                 R"({"name": "floor", "shape": "ground", "static": true, "material": "ice"},
                    {"name": "box", "shape": "block", "mass": 4, "position": [0, 0.5, 0]})",
                 R"({"type": "grid", "shape": "crate", "mass": 1, "count": [3, 1, 3],
                     "origin": [-3, 0.25, -0.6], "spacing": [0.6, 0.6, 0.6], "name_prefix": "d",
                     "linear_velocity": [6, 0, 0], "debris": true})");
}

// Two-way: nine crates sliding at 6 m/s on frictionless ground hit a 4 kg box and push it.
// Nothing horizontal acts from outside (gravity and the ground's normal are vertical), so the
// horizontal momentum of all bodies, counting the impulses not yet applied, stays 54 kg m/s to
// 1e-3 of it (float sums over 60 steps); one-way, the box never moves.
TEST_F(DebrisOffload, TwoWayStreamPushesABoxAndKeepsMomentum) {
    World w = deviceWorld(stream("two-way"));
    const std::uint32_t box = *w.findBody("box");
    const glm::dvec3 p0 = horizontalMomentum(w);
    ASSERT_NEAR(p0.x, 54.0, 1e-4);
    for (int i = 0; i < 60; ++i) {
        ASSERT_TRUE(w.step().ok()) << "step " << i;
        const glm::dvec3 p = horizontalMomentum(w);
        ASSERT_NEAR(p.x, p0.x, 1e-3 * 54.0) << "step " << i;
        ASSERT_NEAR(p.z, p0.z, 1e-3 * 54.0) << "step " << i;
    }
    EXPECT_GT(w.body(box).linearVelocity.x, 0.5f);
    EXPECT_GT(w.body(box).position.x, 0.2f);

    World oneWay = deviceWorld(stream("one-way"));
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(oneWay.step().ok());
    EXPECT_NEAR(oneWay.body(box).position.x, 0.0f, 1e-6f);
}

// Sixteen crates on the floor fall asleep: then no contact and no row is made for them; an
// explosion at t = 2 s wakes those it reaches and throws them.
TEST_F(DebrisOffload, SleepingDebrisCostsNoRowsAndAnExplosionWakesIt) {
    World w = deviceWorld(scene("", kFloor, R"({"type": "grid", "shape": "crate", "mass": 1,
        "count": [4, 1, 4], "origin": [-0.9, 0.25, -0.9], "spacing": [0.6, 0.6, 0.6],
        "name_prefix": "d"})",
                                R"(, "events": [{"type": "explosion", "time": 2.0,
        "centre": [0, -0.5, 0], "impulse": 5, "radius": 4}])"));
    for (int i = 0; i < 110; ++i) ASSERT_TRUE(w.step().ok());
    EXPECT_EQ(w.lastStep().deviceAsleep, 16u);
    EXPECT_EQ(w.lastStep().contactCount, 0u);
    for (std::uint32_t i = 1; i < w.bodyCount(); ++i) EXPECT_TRUE(w.body(i).asleep);
    while (w.time() < 2.0 + 1e-6) ASSERT_TRUE(w.step().ok());
    EXPECT_EQ(w.lastStep().deviceAsleep, 0u);
    for (std::uint32_t i = 1; i < w.bodyCount(); ++i) {
        EXPECT_FALSE(w.body(i).asleep);
        EXPECT_GT(w.body(i).linearVelocity.y, 0.5f) << w.bodyName(i);
    }
}

// The debris flag and coupling change nothing on the cpu backend: the same bits as the scene
// without them.
TEST_F(DebrisOffload, OffloadingChangesNothingOnTheCpuBackend) {
    const std::string bodies = std::string(kFloor) + R"(, {"name": "box", "shape": "block",
        "mass": 4, "position": [3, 0.5, 0]})";
    std::string flagged = scene(R"(, "coupling": "two-way")", bodies,
                                std::string(kRagdoll) + R"(, {"type": "grid", "shape": "crate",
        "mass": 1, "count": [3, 2, 3], "origin": [-0.6, 2.5, -0.6], "spacing": [0.6, 0.6, 0.6],
        "rotation_jitter": 0.2, "seed": 4, "name_prefix": "d", "debris": true})");
    std::string plain = flagged;
    plain.replace(plain.find(R"(, "coupling": "two-way")"), 23, "");
    plain.replace(plain.find(R"(, "debris": true)"), 16, "");
    for (std::string* s : {&flagged, &plain}) s->replace(s->find("\"jacobi\""), 8, "\"pgs\"");
    World a = test::worldFromText(flagged), b = test::worldFromText(plain);
    for (int i = 0; i < 90; ++i) {
        ASSERT_TRUE(a.step().ok());
        ASSERT_TRUE(b.step().ok());
    }
    ASSERT_EQ(a.bodyCount(), b.bodyCount());
    for (std::uint32_t i = 0; i < a.bodyCount(); ++i)
        EXPECT_TRUE(test::sameBits(a.body(i), b.body(i))) << a.bodyName(i);
}

// An explosion reaches both populations once: a CPU crate and a debris crate in free fall, each
// 1 m from the centre of a 4 N s blast of radius 2 m, get 2 N s straight away from it in the
// first step (1 kg: 2 m/s) and keep it; a crate beyond the radius gets nothing.
TEST_F(DebrisOffload, ExplosionReachesBothPopulationsOnce) {
    std::string text = scene("", R"({"name": "cpu", "shape": "crate", "mass": 1,
        "position": [-1, 5, 0]}, {"name": "far", "shape": "crate", "mass": 1,
        "position": [0, 5, 3]}, {"name": "debris", "shape": "crate", "mass": 1, "debris": true,
        "position": [1, 5, 0]})",
                             "", R"(, "events": [{"type": "explosion", "time": 0.0,
        "centre": [0, 5, 0], "impulse": 4, "radius": 2}])");
    World w = deviceWorld(text);
    ASSERT_FALSE(w.onDevice(*w.findBody("cpu")));
    const std::uint32_t cpu = *w.findBody("cpu"), far = *w.findBody("far"),
                        debris = *w.findBody("debris");
    const float fall = -9.81f * 0.016666667f;
    for (int i = 1; i <= 10; ++i) {
        ASSERT_TRUE(w.step().ok()) << "step " << i;
        const glm::vec3 vc = w.body(cpu).linearVelocity, vd = w.body(debris).linearVelocity;
        const glm::vec3 vf = w.body(far).linearVelocity;
        EXPECT_NEAR(vc.x, -2.0f, 1e-5f) << "step " << i;
        EXPECT_NEAR(vd.x, 2.0f, 1e-5f) << "step " << i;
        EXPECT_NEAR(vf.x, 0.0f, 1e-6f) << "step " << i;
        for (const glm::vec3& v : {vc, vd, vf}) {
            EXPECT_NEAR(v.y, float(i) * fall, 1e-4f) << "step " << i;
            EXPECT_NEAR(v.z, 0.0f, 1e-6f) << "step " << i;
        }
    }
}

// The combinations on opencl, as the scene format's contract has them: a scene that names no
// collision method collides with particles, and solves them with pgs when it names no solver;
// a debris set runs with particles and jacobi whatever solver it names (pgs, named or not, is
// the CPU half's); pgs with particles and no debris set solves the particles with PGS on the
// device, but not beside jointed bodies coupled two ways (refused naming coupling and the ways
// out); naming sat gives SAT and PGS, every body on the device.
TEST(DebrisSolver, OpenClDefaultsToParticlesAndPgsAndSatIsNamed) {
    std::string text = scene("", std::string(kFloor) + R"(, {"name": "box", "shape": "block",
        "mass": 4, "position": [3, 0.5, 0]}, {"name": "d", "shape": "crate", "mass": 1,
        "debris": true, "position": [0, 0.25, 0]})",
                             "");
    Result<Scene> withSet = parseScene(text, "inline.json", ".");
    ASSERT_TRUE(withSet.ok());
    withSet->simulation.backend = Backend::OpenCl;
    EXPECT_TRUE(checkBackendCombination(*withSet).ok()); // particles and jacobi, as named

    // Nothing named: particles and pgs; a debris set takes jacobi.
    Scene unnamed = *withSet;
    unnamed.simulation.collision.method.reset();
    unnamed.simulation.solver.type.reset();
    EXPECT_EQ(unnamed.simulation.collisionMethod(), CollisionMethod::Particles);
    EXPECT_EQ(unnamed.simulation.solverType(), SolverType::Pgs);
    EXPECT_EQ(deviceSolver(unnamed), SolverType::Jacobi);
    EXPECT_TRUE(checkBackendCombination(unnamed).ok());
    Scene unnamedWithoutSet = unnamed;
    for (BodyDesc& b : unnamedWithoutSet.bodies) b.debris = false;
    EXPECT_EQ(deviceSolver(unnamedWithoutSet), SolverType::Pgs);
    EXPECT_TRUE(checkBackendCombination(unnamedWithoutSet).ok());

    // pgs named with a debris set: the CPU half's solver, the set takes jacobi.
    Scene pgs = unnamed;
    pgs.simulation.solver.type = SolverType::Pgs;
    EXPECT_EQ(deviceSolver(pgs), SolverType::Jacobi);
    EXPECT_TRUE(checkBackendCombination(pgs).ok());

    // Without a debris set, pgs solves the particles on the device.
    Scene pgsWithoutSet = pgs;
    for (BodyDesc& b : pgsWithoutSet.bodies) b.debris = false;
    EXPECT_EQ(deviceSolver(pgsWithoutSet), SolverType::Pgs);
    EXPECT_TRUE(checkBackendCombination(pgsWithoutSet).ok());
    // Jointed bodies step on the CPU: coupled two ways, their impulses would come from the
    // Jacobi rows, so that is refused, naming coupling and the ways out; one way is not.
    Result<Scene> jointed = parseScene(
        scene("", std::string(kFloor) + R"(, {"name": "a", "shape": "crate", "mass": 1,
        "position": [3, 0.25, 0]}, {"name": "b", "shape": "crate", "mass": 1,
        "position": [3, 0.75, 0]})",
              "", R"(, "joints": [{"type": "ball", "a": "a", "b": "b", "anchor": [3, 0.5, 0]}])"),
        "inline.json", ".");
    ASSERT_TRUE(jointed.ok()) << jointed.error().describe();
    jointed->simulation.backend = Backend::OpenCl;
    jointed->simulation.collision.method = CollisionMethod::Particles;
    jointed->simulation.solver.type = SolverType::Pgs;
    jointed->simulation.coupling = Coupling::OneWay;
    EXPECT_TRUE(checkBackendCombination(*jointed).ok());
    jointed->simulation.coupling = Coupling::TwoWay;
    const Status refused = checkBackendCombination(*jointed);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().where, "inline.json: simulation.coupling");
    for (const char* way : {"--collision sat", "--solver jacobi", "one way"})
        EXPECT_NE(refused.error().message.find(way), std::string::npos)
            << way << ": " << refused.error().message;

    // Naming sat gives SAT and PGS (its default there), with or without a debris set.
    Scene sat = unnamed;
    sat.simulation.collision.method = CollisionMethod::Sat;
    EXPECT_EQ(sat.simulation.solverType(), SolverType::Pgs);
    EXPECT_TRUE(checkBackendCombination(sat).ok());
    pgsWithoutSet.simulation.collision.method = CollisionMethod::Sat;
    EXPECT_TRUE(checkBackendCombination(pgsWithoutSet).ok());

    // SAT with the Jacobi family is refused on the device, and lemke everywhere on it.
    Scene satJacobi = *withSet;
    satJacobi.simulation.collision.method = CollisionMethod::Sat;
    EXPECT_FALSE(checkBackendCombination(satJacobi).ok());
    withSet->simulation.solver.type = SolverType::Lemke;
    EXPECT_FALSE(checkBackendCombination(*withSet).ok());
}

// With SAT the device steps every body, the debris set's and the others alike: no CPU world.
TEST_F(DebrisOffload, SatPutsEveryBodyOnTheDevice) {
    std::string text = scene("", std::string(kFloor) + R"(, {"name": "box", "shape": "block",
        "mass": 4, "position": [3, 0.5, 0]}, {"name": "d", "shape": "crate", "mass": 1,
        "debris": true, "position": [0, 0.25, 0]})",
                             "");
    text.replace(text.find("\"jacobi\""), 8, "\"pgs\"");
    text.replace(text.find("\"particles\""), 11, "\"sat\"");
    World w = deviceWorld(text);
    EXPECT_TRUE(w.onDevice(*w.findBody("box")));
    EXPECT_TRUE(w.onDevice(*w.findBody("d")));
    for (int i = 0; i < 30; ++i) ASSERT_TRUE(w.step().ok());
    // Both rest on the floor: the crate's centre at its half height, 0.25 m, within the slop.
    EXPECT_NEAR(w.body(*w.findBody("d")).position.y, 0.25f, 0.01f);
    EXPECT_NEAR(w.body(*w.findBody("box")).position.y, 0.5f, 0.01f);
}

// The explosion kernel against forces.cpp on the same bodies: the same momenta, bit for bit
// (both call explosionImpulseItem); the body at the centre goes straight up.
TEST_F(DebrisOffload, ExplosionKernelMatchesTheCpu) {
    auto d =
        deviceStage(scene("", kFloor, R"({"type": "grid", "shape": "crate", "mass": 2,
        "count": [5, 4, 5], "origin": [-1.2, 0.25, -1.2], "spacing": [0.6, 0.6, 0.6],
        "rotation_jitter": 0.3, "seed": 9, "name_prefix": "d"})"));
    BodyArrays& s = d->in.bodies;
    const EventDesc e{"test", 0.0f, glm::vec3(0.0f, 0.25f, 0.0f), 7.0f, 2.0f};
    ASSERT_TRUE(gpu::applyExplosion(d->q(), d->bodies, e).ok());
    const std::size_t reached = applyExplosion(e, s.poses, s.masses, s.momenta);
    EXPECT_GT(reached, 10u);
    EXPECT_LT(reached, 99u);
    std::vector<shared::BodyMomentum> device(s.count());
    ASSERT_TRUE(gpu::download(d->context(), d->bodies.momenta, std::span(device)).ok());
    for (std::uint32_t i = 0; i < s.count(); ++i)
        EXPECT_EQ(std::memcmp(&device[i], &s.momenta[i], sizeof device[i]), 0) << i;
    const std::uint32_t centre = *d->in.scene.findBody("d42"); // (0, 0.25, 0): x 2, y 0, z 2
    EXPECT_FLOAT_EQ(s.momenta[centre].linear.y, 7.0f);
}

// 64 crates dropped in a block, deterministic mode: the device and its CPU twin (cpu backend,
// particles and jacobi) fall asleep alike, body for body, and stay equal to 1e-5 m.
TEST_F(DebrisOffload, SleepingMatchesTheCpuTwin) {
    const std::string text = scene("", kFloor, R"({"type": "grid", "shape": "crate", "mass": 1,
        "count": [4, 4, 4], "origin": [-0.9, 0.3, -0.9], "spacing": [0.6, 0.55, 0.6],
        "rotation_jitter": 0.05, "seed": 3, "name_prefix": "d"})");
    Result<Scene> parsed = parseScene(text, "inline.json", ".");
    ASSERT_TRUE(parsed.ok());
    Result<World> cpu = World::create(*parsed);
    ASSERT_TRUE(cpu.ok()) << cpu.error().describe();
    World device = deviceWorld(text, true);
    std::uint32_t sawAsleep = 0;
    for (int i = 0; i < 150; ++i) {
        ASSERT_TRUE(cpu->step().ok());
        ASSERT_TRUE(device.step().ok());
        sawAsleep = std::max(sawAsleep, device.lastStep().deviceAsleep);
    }
    EXPECT_GT(sawAsleep, 32u);
    EXPECT_EQ(device.lastStep().asleep, cpu->lastStep().asleep);
    for (std::uint32_t i = 0; i < cpu->bodyCount(); ++i) {
        EXPECT_EQ(device.body(i).asleep, cpu->body(i).asleep) << i;
        EXPECT_LT(glm::length(device.body(i).position - cpu->body(i).position), 1e-5f) << i;
    }
}

// The host API: 50 crates added in bulk to a world on the device fall with the others, their
// transforms read straight from the device equal World::body's, and those that left a box go.
TEST_F(DebrisOffload, DebrisIsAddedInBulkDrawnAndRemoved) {
    World w = deviceWorld(scene("", kFloor, R"({"type": "grid", "shape": "crate", "mass": 1,
        "count": [2, 1, 2], "origin": [0, 0.25, 0], "spacing": [0.6, 0.6, 0.6],
        "name_prefix": "d"})"));
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(w.step().ok());
    std::vector<DebrisPiece> pieces(50);
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        pieces[k].name = "added" + std::to_string(k);
        pieces[k].shape = *w.findShape("crate");
        pieces[k].position =
            glm::vec3(-6.0f + 0.6f * float(k % 10), 1.0f + 0.6f * float(k / 10), 3.0f);
        pieces[k].linearVelocity = glm::vec3(k < 25 ? -20.0f : 0.0f, 0.0f, 0.0f);
    }
    Result<std::uint32_t> first = w.addDebris(pieces);
    ASSERT_TRUE(first.ok()) << first.error().describe();
    EXPECT_EQ(*first, 5u);
    EXPECT_EQ(w.bodyCount(), 55u);
    for (int i = 0; i < 30; ++i) ASSERT_TRUE(w.step().ok());
    std::vector<BodyTransform> drawn(w.bodyCount());
    ASSERT_TRUE(w.readTransforms(0, drawn).ok());
    for (std::uint32_t i = 0; i < w.bodyCount(); ++i) {
        const BodyState b = w.body(i);
        EXPECT_EQ(glm::vec3(drawn[i].position), b.position) << i;
        EXPECT_EQ(drawn[i].orientation, b.orientation) << i;
    }
    // The 25 thrown at 20 m/s are 10 m away after half a second.
    Result<std::uint32_t> removed =
        w.removeDebrisOutside(glm::vec3(-8.0f, -1.0f, -8.0f), glm::vec3(8.0f, 10.0f, 8.0f));
    ASSERT_TRUE(removed.ok()) << removed.error().describe();
    EXPECT_EQ(*removed, 25u);
    EXPECT_EQ(w.bodyCount(), 30u);
    EXPECT_EQ(w.bodyName(5), "added25");
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(w.step().ok());
    std::vector<BodyTransform> pastTheEnd(6);
    EXPECT_FALSE(w.readTransforms(25, pastTheEnd).ok());
    // Bad pieces are refused, naming the field.
    pieces.resize(1);
    pieces[0].mass = -1.0f;
    Result<std::uint32_t> bad = w.addDebris(pieces);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().where, "addDebris: pieces[0].mass");
}

} // namespace
} // namespace rubble
