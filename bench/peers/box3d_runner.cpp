// bench/peers/box3d_runner.cpp: a rubble scene on Box3D (soft step solver, graph coloring, SIMD),
// with one worker or several on a thread pool of its task callbacks: same bodies, sizes, masses,
// inertias, materials, gravity and dt; Box3D's own substeps.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include <CLI/CLI.hpp>
#include <glm/gtx/quaternion.hpp>

#include <box3d/box3d.h>
#include <box3d/collision.h>

#include "peer.h"
#include "task_pool.h"

namespace rubble::peers {
namespace {

// Box3D's benchmark program steps every scene with 4 substeps (benchmark/main.c).
constexpr int kSubsteps = 4;
// A plane becomes a static box this thick (half extent, m) whose top face is the plane, and at
// least this wide (half extent, m): wider when the scene's bodies reach further.
constexpr float kPlaneHalfThickness = 1.0f;
constexpr float kPlaneMinHalfWidth = 100.0f;

b3Vec3 b3(glm::vec3 v) { return b3Vec3{v.x, v.y, v.z}; }
b3Quat b3(glm::quat q) { return b3Quat{b3Vec3{q.x, q.y, q.z}, q.w}; }
glm::vec3 fromB3(b3Vec3 v) { return {v.x, v.y, v.z}; }
glm::quat fromB3(b3Quat q) { return glm::quat(q.s, q.v.x, q.v.y, q.v.z); }

b3Matrix3 b3(const glm::dmat3& m) {
    auto column = [&](int c) {
        return b3Vec3{float(m[c][0]), float(m[c][1]), float(m[c][2])};
    };
    return b3Matrix3{column(0), column(1), column(2)};
}

// The task callbacks of b3WorldDef over a TaskPool (the world's userTaskContext).
void* enqueueTask(b3TaskCallback* task, void* taskContext, void* userContext, const char*) {
    return static_cast<TaskPool*>(userContext)->enqueue(task, taskContext);
}
void finishTask(void* userTask, void* userContext) {
    static_cast<TaskPool*>(userContext)->finish(static_cast<TaskPool::Task*>(userTask));
}

// A Box3D hull for one rubble shape (box, convex, mesh: rubble's hull, centre of mass at the
// origin); null for spheres and planes, which are made per body. A mesh that static bodies use
// (a static triangle mesh or a height field, rubble's level mesh) is also a Box3D triangle mesh.
struct Box3dShape {
    b3HullData* hull = nullptr; ///< owned (b3DestroyHull), unless it is `box`'s
    b3MeshData* mesh = nullptr; ///< owned (b3DestroyMesh): the level mesh's triangles
    b3BoxHull box{};
    bool isBox = false;
    bool reduced = false; ///< the hull has more vertices than Box3D takes: Box3D reduced it

    const b3HullData* data() const { return isBox ? &box.base : hull; }
};

class Box3dWorld final : public PeerWorld {
  public:
    Box3dWorld(const Scene& scene, const std::vector<Shape>& shapes, int workers)
        : workers_(workers) {
        b3WorldDef def = b3DefaultWorldDef();
        def.gravity = b3(scene.simulation.gravity);
        def.enableSleep = scene.simulation.sleep;
        def.workerCount = std::uint32_t(workers);
        // One worker steps on the calling thread (Box3D's serial path); N use a pool of N - 1
        // threads and the calling thread, which runs queued tasks while it waits.
        if (workers > 1) {
            pool_ = std::make_unique<TaskPool>(workers - 1);
            def.enqueueTask = enqueueTask;
            def.finishTask = finishTask;
            def.userTaskContext = pool_.get();
        }
        for (const BodyDesc& d : scene.bodies) {
            b3Capacity& c = def.capacity;
            (d.isStatic ? c.staticBodyCount : c.dynamicBodyCount) += 1;
            (d.isStatic ? c.staticShapeCount : c.dynamicShapeCount) += 1;
        }
        // The shapes that static bodies use: their meshes collide by their triangles.
        std::vector<std::uint8_t> staticUse(shapes.size(), 0);
        for (const BodyDesc& d : scene.bodies)
            if (d.isStatic) staticUse[d.shape] = 1;
        world_ = b3CreateWorld(&def);
        dt_ = scene.simulation.dt;
        for (std::size_t i = 0; i < shapes.size(); ++i)
            shapes_.push_back(makeShape(shapes[i], staticUse[i] != 0));
        const float planeHalfWidth = planeWidth(scene, shapes);
        for (const BodyDesc& d : scene.bodies) addBody(scene, shapes, d, planeHalfWidth);
        for (const JointDesc& j : scene.joints) addJoint(j);
    }
    ~Box3dWorld() override {
        b3DestroyWorld(world_);
        for (Box3dShape& s : shapes_) {
            if (s.hull) b3DestroyHull(s.hull);
            if (s.mesh) b3DestroyMesh(s.mesh);
        }
    }

    bool valid() const { return bad_.empty(); }
    const std::string& problem() const { return bad_; }

    void step() override { b3World_Step(world_, dt_, kSubsteps); }

    bool applyImpulse(std::size_t body, glm::vec3 impulse) override {
        b3Body_ApplyLinearImpulseToCenter(bodies_[body], b3(impulse), true);
        return true;
    }

    void read(std::vector<TrajectoryRow>& rows) const override {
        rows.resize(bodies_.size());
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
            // A static body is where the scene put it (a plane's box is not the plane's pose).
            if (!dynamic_[i]) {
                rows[i] = staticRows_[i];
                rows[i].body = names_[i];
                continue;
            }
            const b3BodyId b = bodies_[i];
            rows[i] = TrajectoryRow{names_[i], fromB3(b3Body_GetWorldCenter(b)),
                                    glm::normalize(fromB3(b3Body_GetRotation(b))),
                                    fromB3(b3Body_GetLinearVelocity(b)),
                                    fromB3(b3Body_GetAngularVelocity(b))};
        }
    }

    std::optional<std::size_t> asleep() const override {
        std::size_t n = 0;
        for (std::size_t i = 0; i < bodies_.size(); ++i)
            n += dynamic_[i] && !b3Body_IsAwake(bodies_[i]) ? 1 : 0;
        return n;
    }

    std::string device() const override {
        return "box3d, " + std::to_string(workers_) + (workers_ == 1 ? " worker" : " workers");
    }

    std::vector<std::string> caveats() const override {
        std::vector<std::string> c = {
            std::to_string(kSubsteps) + " substeps of Box3D's soft step solver per step, as its "
                                        "benchmark (the scene's solver settings do not apply)",
            "continuous collision and contact recycling on (Box3D's defaults)",
            "planes are static boxes 2 m thick whose top face is the plane",
            "mass, centre and inertia set to rubble's (b3Body_SetMassData)",
            "sleeping by Box3D's rules when the scene's sleep is true (0.05 m/s, 0.5 s)",
            workers_ == 1 ? "1 worker: Box3D's serial path on the calling thread"
                          : std::to_string(workers_) + " workers: a pool of " +
                                std::to_string(workers_ - 1) +
                                " threads and the calling thread on Box3D's task callbacks"};
        for (const Box3dShape& s : shapes_)
            if (s.reduced) {
                c.push_back("a hull of more vertices than Box3D takes is reduced by Box3D");
                break;
            }
        return c;
    }

  private:
    Box3dShape makeShape(const Shape& s, bool usedStatic) {
        Box3dShape b;
        if (usedStatic && s.level) b.mesh = makeMesh(s);
        switch (s.type) {
        case ShapeType::Box:
            b.box = b3MakeBoxHull(s.halfExtents.x, s.halfExtents.y, s.halfExtents.z);
            b.isBox = true;
            break;
        case ShapeType::Convex:
        case ShapeType::Mesh: {
            // A level mesh that encloses no volume has no hull; static bodies use its triangles.
            if (s.hull.vertices.empty()) break;
            std::vector<b3Vec3> points;
            for (const glm::vec3& v : s.hull.vertices) points.push_back(b3(v));
            const int n = int(points.size());
            b.hull = b3CreateHull(points.data(), n, std::min(n, B3_MAX_HULL_VERTICES));
            // Past Box3D's face and edge limits: let it pick fewer vertices.
            for (int most = 32; !b.hull && most >= 8; most /= 2) {
                b.hull = b3CreateHull(points.data(), n, most);
                b.reduced = true;
            }
            if (!b.hull && bad_.empty()) bad_ = "shapes." + s.name + ": Box3D cannot make its hull";
            break;
        }
        case ShapeType::Sphere:
        case ShapeType::Capsule:
        case ShapeType::Plane:
            break;
        }
        return b;
    }

    // A Box3D triangle mesh of a level mesh's triangles (rubble's winding, vertices welded, edges
    // shared so that Box3D's own internal-edge handling applies).
    b3MeshData* makeMesh(const Shape& s) {
        std::vector<b3Vec3> vertices;
        std::vector<std::int32_t> indices;
        std::vector<std::uint8_t> materials;
        for (const LevelTriangle& t : s.level->triangles) {
            for (const glm::vec3& v : t.v) {
                indices.push_back(std::int32_t(vertices.size()));
                vertices.push_back(b3(v));
            }
            materials.push_back(0);
        }
        b3MeshDef def{};
        def.vertices = vertices.data();
        def.indices = indices.data();
        def.materialIndices = materials.data();
        def.vertexCount = int(vertices.size());
        def.triangleCount = int(materials.size());
        def.weldVertices = true;
        def.weldTolerance = 1e-5f;
        def.identifyEdges = true;
        b3MeshData* mesh = b3CreateMesh(&def, nullptr, 0);
        if (!mesh && bad_.empty()) bad_ = "shapes." + s.name + ": Box3D cannot make its mesh";
        return mesh;
    }

    // Half the width of a plane's box: past every body of the scene with room to spare.
    static float planeWidth(const Scene& scene, const std::vector<Shape>& shapes) {
        float reach = 0.0f;
        for (const BodyDesc& d : scene.bodies) {
            if (shapes[d.shape].type == ShapeType::Plane) continue;
            const glm::vec3 p = glm::abs(d.position);
            reach = std::max(reach, std::max(p.x, std::max(p.y, p.z)) +
                                        shapes[d.shape].boundingRadius);
        }
        return std::max(kPlaneMinHalfWidth, 2.0f * reach);
    }

    void addBody(const Scene& scene, const std::vector<Shape>& shapes, const BodyDesc& d,
                 float planeHalfWidth) {
        const Shape& shape = shapes[d.shape];
        const MaterialDesc& material = scene.materials[d.material];
        b3BodyDef body = b3DefaultBodyDef();
        body.type = d.isStatic      ? b3_staticBody
                    : d.isKinematic ? b3_kinematicBody
                                    : b3_dynamicBody;
        const bool massive = !d.isStatic && !d.isKinematic;
        body.position = b3(d.position);
        body.rotation = b3(d.orientation);
        body.linearVelocity = b3(d.linearVelocity);
        body.angularVelocity = b3(d.angularVelocity);
        body.name = d.name.c_str();
        b3BoxHull planeBox{};
        if (shape.type == ShapeType::Plane) {
            // The box's +y face on the plane: rotated from y to the normal, centred below it.
            const glm::vec3 n = glm::normalize(shape.normal);
            const glm::quat q = d.orientation * glm::rotation(glm::vec3(0.0f, 1.0f, 0.0f), n);
            body.rotation = b3(q);
            body.position =
                b3(d.position + d.orientation * (n * (shape.offset - kPlaneHalfThickness)));
            planeBox = b3MakeBoxHull(planeHalfWidth, kPlaneHalfThickness, planeHalfWidth);
        }
        const b3BodyId id = b3CreateBody(world_, &body);
        b3ShapeDef def = b3DefaultShapeDef();
        def.baseMaterial.friction = material.friction;
        def.baseMaterial.restitution = material.restitution;
        const double mass = massive ? bodyMass(d, shape) : 0.0;
        def.density = massive ? float(mass / shape.unitMass.volume) : 0.0f;
        def.updateBodyMass = false;
        if (shape.type == ShapeType::Sphere) {
            const b3Sphere sphere{b3Vec3{0.0f, 0.0f, 0.0f}, shape.radius};
            b3CreateSphereShape(id, &def, &sphere);
        } else if (shape.type == ShapeType::Capsule) {
            // rubble's capsule: the segment from (0, -h, 0) to (0, h, 0), radius r.
            const b3Capsule capsule{b3Vec3{0.0f, -shape.halfHeight, 0.0f},
                                    b3Vec3{0.0f, shape.halfHeight, 0.0f}, shape.radius};
            b3CreateCapsuleShape(id, &def, &capsule);
        } else if (shape.type == ShapeType::Plane) {
            b3CreateHullShape(id, &def, &planeBox.base);
        } else if (d.isStatic && shapes_[d.shape].mesh) {
            b3CreateMeshShape(id, &def, shapes_[d.shape].mesh, b3Vec3{1.0f, 1.0f, 1.0f});
        } else if (const b3HullData* hull = shapes_[d.shape].data()) {
            b3CreateHullShape(id, &def, hull);
        }
        if (massive) {
            // rubble's mass properties: the centre of mass at the body's origin.
            const glm::dmat3 inertia = shape.unitMass.inertia * (mass / shape.unitMass.volume);
            b3Body_SetMassData(id, b3MassData{float(mass), b3Vec3{0.0f, 0.0f, 0.0f}, b3(inertia)});
        }
        bodies_.push_back(id);
        dynamic_.push_back(!d.isStatic); // kinematic bodies move: read like dynamic ones
        staticRows_.push_back(TrajectoryRow{d.name, d.position, d.orientation, glm::vec3(0.0f),
                                            glm::vec3(0.0f)});
        names_.push_back(d.name);
    }

    // A joint from its world anchor (and axis) at the initial pose, as rubble builds it: ball
    // -> spherical, hinge -> revolute about the frames' z axis. The two bodies do not collide.
    void addJoint(const JointDesc& j) {
        const b3BodyId a = bodies_[j.a], b = bodies_[j.b];
        const b3Pos anchor = b3(j.anchor);
        if (j.type == JointType::Ball) {
            b3SphericalJointDef def = b3DefaultSphericalJointDef();
            def.base.bodyIdA = a;
            def.base.bodyIdB = b;
            def.base.localFrameA.p = b3Body_GetLocalPoint(a, anchor);
            def.base.localFrameB.p = b3Body_GetLocalPoint(b, anchor);
            b3CreateSphericalJoint(world_, &def);
            return;
        }
        b3RevoluteJointDef def = b3DefaultRevoluteJointDef();
        def.base.bodyIdA = a;
        def.base.bodyIdB = b;
        def.base.localFrameA.p = b3Body_GetLocalPoint(a, anchor);
        def.base.localFrameB.p = b3Body_GetLocalPoint(b, anchor);
        const glm::quat toAxis =
            glm::rotation(glm::vec3(0.0f, 0.0f, 1.0f), glm::normalize(j.axis));
        def.base.localFrameA.q = b3(glm::conjugate(fromB3(b3Body_GetRotation(a))) * toAxis);
        def.base.localFrameB.q = b3(glm::conjugate(fromB3(b3Body_GetRotation(b))) * toAxis);
        b3CreateRevoluteJoint(world_, &def);
    }

    int workers_ = 1;
    std::unique_ptr<TaskPool> pool_; ///< the world's task callbacks' (its threads end last)
    b3WorldId world_{};
    float dt_ = 1.0f / 60.0f;
    std::vector<Box3dShape> shapes_;
    std::vector<b3BodyId> bodies_;
    std::vector<std::uint8_t> dynamic_;
    std::vector<TrajectoryRow> staticRows_; ///< each body's pose in the scene, at rest
    std::vector<std::string> names_;
    std::string bad_;
};

} // namespace
} // namespace rubble::peers

int main(int argc, char** argv) {
    using namespace rubble;
    // 0: one per hardware thread.
    int workers = 1;
    auto options = [&workers](CLI::App& app) {
        app.add_option("--workers", workers,
                       "Box3D workers: 1 steps on the calling thread, 0 one per core")
            ->check(CLI::Range(0, B3_MAX_WORKERS));
    };
    const std::string version = std::string("0.1.0 (") + std::string(RUBBLE_BOX3D_COMMIT).substr(0, 7) + ")";
    return peers::runPeer(
        argc, argv, "box3d", version,
        [&workers](const Scene& scene,
                   const std::vector<Shape>& shapes) -> Result<std::unique_ptr<peers::PeerWorld>> {
            const int n = workers > 0 ? workers
                                      : std::clamp(int(std::thread::hardware_concurrency()), 1,
                                                   B3_MAX_WORKERS);
            auto world = std::make_unique<peers::Box3dWorld>(scene, shapes, n);
            if (!world->valid())
                return makeError(ErrorKind::NotSupported, scene.name, world->problem());
            return std::unique_ptr<peers::PeerWorld>(std::move(world));
        },
        options);
}
