// bench/peers/bullet_runner.cpp: a rubble scene on Bullet 2's btDiscreteDynamicsWorld with the
// sequential impulse solver, single-threaded: same bodies, sizes, masses, dt and iterations.
#include <cmath>

#include <btBulletDynamicsCommon.h>

#include "host/core/math.h"
#include "peer.h"

namespace rubble::peers {
namespace {

btVector3 bt(glm::vec3 v) { return btVector3(v.x, v.y, v.z); }
glm::vec3 fromBt(const btVector3& v) { return {float(v.x()), float(v.y()), float(v.z())}; }
glm::quat fromBt(const btQuaternion& q) {
    return glm::quat(float(q.w()), float(q.x()), float(q.y()), float(q.z()));
}
btQuaternion bt(glm::quat q) { return btQuaternion(q.x, q.y, q.z, q.w); }

// A Bullet collision shape for one rubble shape, in Bullet's body frame: the principal axes of
// rubble's inertia (Bullet keeps a diagonal inertia), reached from the shape's frame by `toBody`.
struct BulletShape {
    std::unique_ptr<btCollisionShape> shape;
    std::unique_ptr<btCollisionShape> child; // a hull inside a compound, when rotated
    // A mesh that static bodies use (a static triangle mesh or a height field): its triangles in
    // the body frame, as rubble's level mesh holds them.
    std::unique_ptr<btTriangleMesh> triangles;
    std::unique_ptr<btCollisionShape> level;
    glm::quat toBody{1.0f, 0.0f, 0.0f, 0.0f}; // shape frame -> Bullet body frame
    glm::dvec3 moments{0.0};                  // principal moments at unit density
};

BulletShape makeShape(const Shape& s, bool usedStatic) {
    BulletShape b;
    if (usedStatic && s.level) {
        b.triangles = std::make_unique<btTriangleMesh>();
        for (const LevelTriangle& t : s.level->triangles)
            b.triangles->addTriangle(bt(t.v[0]), bt(t.v[1]), bt(t.v[2]));
        b.level = std::make_unique<btBvhTriangleMeshShape>(b.triangles.get(), true);
    }
    switch (s.type) {
    case ShapeType::Box:
        b.shape = std::make_unique<btBoxShape>(bt(s.halfExtents));
        break;
    case ShapeType::Sphere:
        b.shape = std::make_unique<btSphereShape>(s.radius);
        break;
    case ShapeType::Capsule: // Bullet's capsule runs along its local y, as rubble's does
        b.shape = std::make_unique<btCapsuleShape>(s.radius, 2.0f * s.halfHeight);
        break;
    case ShapeType::Plane:
        b.shape = std::make_unique<btStaticPlaneShape>(bt(s.normal), s.offset);
        return b;
    case ShapeType::Convex:
    case ShapeType::Mesh: {
        // A level mesh that encloses no volume has no hull; static bodies use its triangles.
        if (s.hull.vertices.empty()) return b;
        auto hull = std::make_unique<btConvexHullShape>();
        for (const glm::vec3& v : s.hull.vertices) hull->addPoint(bt(v), false);
        hull->recalcLocalAabb();
        const PrincipalAxes pa = principalAxes(s.unitMass.inertia);
        b.moments = pa.moments;
        b.toBody = glm::conjugate(glm::quat(pa.axes));
        auto compound = std::make_unique<btCompoundShape>();
        compound->addChildShape(btTransform(bt(b.toBody)), hull.get());
        b.child = std::move(hull);
        b.shape = std::move(compound);
        return b;
    }
    }
    b.moments = glm::dvec3(s.unitMass.inertia[0][0], s.unitMass.inertia[1][1],
                           s.unitMass.inertia[2][2]);
    return b;
}

class BulletWorld final : public PeerWorld {
  public:
    BulletWorld(const Scene& scene, const std::vector<Shape>& shapes)
        : dispatcher_(&config_),
          world_(&dispatcher_, &broadphase_, &solver_, &config_) {
        world_.setGravity(bt(scene.simulation.gravity));
        world_.getSolverInfo().m_numIterations = scene.simulation.solver.iterations;
        dt_ = scene.simulation.dt;
        std::vector<std::uint8_t> staticUse(shapes.size(), 0);
        for (const BodyDesc& d : scene.bodies)
            if (d.isStatic) staticUse[d.shape] = 1;
        for (std::size_t i = 0; i < shapes.size(); ++i)
            shapes_.push_back(makeShape(shapes[i], staticUse[i] != 0));
        for (const BodyDesc& d : scene.bodies) {
            const Shape& shape = shapes[d.shape];
            BulletShape& bs = shapes_[d.shape];
            // A static mesh collides by its triangles, in the body frame.
            const bool level = d.isStatic && bs.level;
            btCollisionShape* collides = level ? bs.level.get() : bs.shape.get();
            const glm::quat toBody = level ? glm::quat(1.0f, 0.0f, 0.0f, 0.0f) : bs.toBody;
            const double mass = bodyMass(d, shape);
            btVector3 inertia(0, 0, 0);
            if (mass > 0.0) {
                const glm::dvec3 m = bs.moments * (mass / shape.unitMass.volume);
                inertia = btVector3(m.x, m.y, m.z);
            }
            // Bullet's body frame is the principal frame: q_bullet = q_shape * toBody^-1.
            const glm::quat q = d.orientation * glm::conjugate(toBody);
            btTransform start(bt(q), bt(d.position));
            motion_.push_back(std::make_unique<btDefaultMotionState>(start));
            btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motion_.back().get(),
                                                          collides, inertia);
            // Bullet multiplies the two bodies' coefficients; rubble takes sqrt(mu_a mu_b).
            const MaterialDesc& mat = scene.materials[d.material];
            info.m_friction = std::sqrt(mat.friction);
            info.m_restitution = mat.restitution;
            auto body = std::make_unique<btRigidBody>(info);
            body->setLinearVelocity(bt(d.linearVelocity));
            body->setAngularVelocity(bt(d.angularVelocity));
            world_.addRigidBody(body.get());
            toShape_.push_back(toBody);
            bodies_.push_back(std::move(body));
            names_.push_back(d.name);
        }
        for (const JointDesc& j : scene.joints) addJoint(j);
    }
    ~BulletWorld() override {
        for (auto& c : joints_) world_.removeConstraint(c.get());
        for (auto& b : bodies_) world_.removeRigidBody(b.get());
    }

    void step() override { world_.stepSimulation(btScalar(dt_), 0, btScalar(dt_)); }

    bool applyImpulse(std::size_t body, glm::vec3 impulse) override {
        btRigidBody& b = *bodies_[body];
        b.activate(true);
        b.applyCentralImpulse(btVector3(impulse.x, impulse.y, impulse.z));
        return true;
    }

    void read(std::vector<TrajectoryRow>& rows) const override {
        rows.resize(bodies_.size());
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
            const btRigidBody& b = *bodies_[i];
            const btTransform& t = b.getCenterOfMassTransform();
            rows[i] = TrajectoryRow{names_[i], fromBt(t.getOrigin()),
                                    glm::normalize(fromBt(t.getRotation()) * toShape_[i]),
                                    fromBt(b.getLinearVelocity()), fromBt(b.getAngularVelocity())};
        }
    }

    std::optional<std::size_t> asleep() const override {
        std::size_t n = 0;
        for (const auto& b : bodies_)
            n += !b->isStaticObject() && b->getActivationState() == ISLAND_SLEEPING ? 1 : 0;
        return n;
    }

    std::vector<std::string> caveats() const override {
        return {"restitution combines as e_a * e_b (rubble: max)",
                "collision margin 0.04 m (Bullet's default; boxes keep their extents)",
                "sleeping by Bullet's defaults (2 s below 0.8 m/s and 1 rad/s)",
                "hulls keep rubble's inertia through a compound in the principal frame"};
    }

  private:
    // A joint from its world anchor and axis at the initial pose, as rubble builds it; the two
    // bodies do not collide with each other.
    void addJoint(const JointDesc& j) {
        btRigidBody& a = *bodies_[j.a];
        btRigidBody& b = *bodies_[j.b];
        const btTransform toA = a.getCenterOfMassTransform().inverse();
        const btTransform toB = b.getCenterOfMassTransform().inverse();
        const btVector3 anchor = bt(j.anchor);
        std::unique_ptr<btTypedConstraint> c;
        if (j.type == JointType::Ball) {
            c = std::make_unique<btPoint2PointConstraint>(a, b, toA * anchor, toB * anchor);
        } else {
            const btVector3 axis = bt(j.axis);
            c = std::make_unique<btHingeConstraint>(a, b, toA * anchor, toB * anchor,
                                                    toA.getBasis() * axis, toB.getBasis() * axis);
        }
        world_.addConstraint(c.get(), true);
        joints_.push_back(std::move(c));
    }

    btDefaultCollisionConfiguration config_;
    btCollisionDispatcher dispatcher_;
    btDbvtBroadphase broadphase_;
    btSequentialImpulseConstraintSolver solver_;
    btDiscreteDynamicsWorld world_;
    float dt_ = 1.0f / 60.0f;
    std::vector<BulletShape> shapes_;
    std::vector<std::unique_ptr<btDefaultMotionState>> motion_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
    std::vector<std::unique_ptr<btTypedConstraint>> joints_;
    std::vector<glm::quat> toShape_;
    std::vector<std::string> names_;
};

} // namespace
} // namespace rubble::peers

int main(int argc, char** argv) {
    using namespace rubble;
    const std::string version = std::to_string(BT_BULLET_VERSION / 100) + "." + std::to_string(BT_BULLET_VERSION % 100);
    return peers::runPeer(argc, argv, "bullet", version,
                          [](const Scene& scene, const std::vector<Shape>& shapes)
                              -> Result<std::unique_ptr<peers::PeerWorld>> {
                              return std::unique_ptr<peers::PeerWorld>(
                                  std::make_unique<peers::BulletWorld>(scene, shapes));
                          });
}
