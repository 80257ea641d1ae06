// bench/peers/mujoco_runner.cpp: a rubble scene on MuJoCo: the scene written as MJCF (free
// bodies, static geoms in the world body), PGS with the same iterations and dt.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>
#include <mujoco/mujoco.h>

#include "host/core/math.h"
#include "host/io/trajectory_writer.h"
#include "peer.h"

namespace rubble::peers {
namespace {

std::string vec(glm::vec3 v) {
    std::ostringstream s;
    s.precision(9);
    s << v.x << ' ' << v.y << ' ' << v.z;
    return s.str();
}
std::string quat(glm::quat q) {
    std::ostringstream s;
    s.precision(9);
    s << q.w << ' ' << q.x << ' ' << q.y << ' ' << q.z;
    return s.str();
}

// The geom element of a shape, with the body's mass when it is dynamic.
std::string geom(const Shape& s, std::size_t shapeIndex, double mass, float friction) {
    std::ostringstream g;
    g.precision(9);
    g << "<geom friction=\"" << friction << " 0.005 0.0001\"";
    switch (s.type) {
    case ShapeType::Box: g << " type=\"box\" size=\"" << vec(s.halfExtents) << "\""; break;
    case ShapeType::Sphere: g << " type=\"sphere\" size=\"" << s.radius << "\""; break;
    case ShapeType::Capsule:
        // MuJoCo's capsule runs along its fromto segment; rubble's along local y.
        g << " type=\"capsule\" size=\"" << s.radius << "\" fromto=\"0 " << -s.halfHeight
          << " 0 0 " << s.halfHeight << " 0\"";
        break;
    case ShapeType::Convex:
    case ShapeType::Mesh: g << " type=\"mesh\" mesh=\"shape" << shapeIndex << "\""; break;
    case ShapeType::Plane: {
        // MuJoCo's plane faces its local +z: turn z onto the normal, move it to the offset.
        const glm::quat q = glm::rotation(glm::vec3(0, 0, 1), s.normal);
        g << " type=\"plane\" size=\"0 0 1\" pos=\"" << vec(s.normal * s.offset) << "\" quat=\""
          << quat(q) << "\"";
        break;
    }
    }
    if (mass > 0.0) g << " mass=\"" << mass << "\"";
    g << "/>";
    return g.str();
}

// Constraint budget per body: MuJoCo's box-box test returns up to eight points, each with four
// rows in the pyramidal cone. MuJoCo 2.2 sizes dense njmax x njmax and njmax x nv arrays from it,
// which limits it to a few hundred free bodies.
constexpr std::size_t kContactsPerBody = 8;
constexpr std::size_t kRowsPerBody = 32;
// Half the distance between the two point constraints that make a hinge, m.
constexpr float kHingeHalfSpan = 0.05f;

class MujocoWorld final : public PeerWorld {
  public:
    static Result<std::unique_ptr<PeerWorld>> create(const Scene& scene,
                                                     const std::vector<Shape>& shapes) {
        auto w = std::unique_ptr<MujocoWorld>(new MujocoWorld());
        std::ostringstream x;
        x.precision(9);
        const std::size_t n = scene.bodies.size();
        x << "<mujoco model=\"rubble\">\n<option timestep=\"" << scene.simulation.dt
          << "\" gravity=\"" << vec(scene.simulation.gravity) << "\" iterations=\""
          << scene.simulation.solver.iterations << "\" solver=\"PGS\" cone=\"pyramidal\" jacobian=\"sparse\"/>\n"
          << "<size nconmax=\"" << kContactsPerBody * n + 100 << "\" njmax=\""
          << kRowsPerBody * n + 400 << "\"/>\n<asset>\n";
        for (std::size_t i = 0; i < shapes.size(); ++i) {
            if (shapes[i].type != ShapeType::Convex && shapes[i].type != ShapeType::Mesh) continue;
            x << "<mesh name=\"shape" << i << "\" vertex=\"";
            for (const glm::vec3& v : shapes[i].hull.vertices) x << vec(v) << ' ';
            x << "\"/>\n";
        }
        x << "</asset>\n<worldbody>\n";
        for (std::size_t i = 0; i < n; ++i) {
            const BodyDesc& d = scene.bodies[i];
            const Shape& s = shapes[d.shape];
            const float mu = scene.materials[d.material].friction;
            if (d.isStatic) {
                std::string g = geom(s, d.shape, 0.0, mu);
                if (s.type != ShapeType::Plane)
                    g.insert(5, " pos=\"" + vec(d.position) + "\" quat=\"" + quat(d.orientation) + "\"");
                x << g << "\n";
                w->bodyOf_.push_back(-1);
                continue;
            }
            x << "<body name=\"" << d.name << "\" pos=\"" << vec(d.position) << "\" quat=\""
              << quat(d.orientation) << "\"><freejoint/>" << geom(s, d.shape, bodyMass(d, s), mu)
              << "</body>\n";
            w->bodyOf_.push_back(int(++w->dynamicCount_));
        }
        x << "</worldbody>\n";
        // Joints between free bodies as equality constraints: a ball joint is one connect, a
        // hinge two connects along its axis (which leaves the one rotation about it free).
        auto bodyName = [&](std::uint32_t i) {
            return w->bodyOf_[i] < 0 ? std::string("world") : scene.bodies[i].name;
        };
        auto localAnchor = [&](std::uint32_t i, glm::vec3 worldPoint) {
            const BodyDesc& d = scene.bodies[i];
            return glm::conjugate(d.orientation) * (worldPoint - d.position);
        };
        if (!scene.joints.empty()) {
            x << "<equality>\n";
            for (const JointDesc& j : scene.joints) {
                std::vector<glm::vec3> anchors{j.anchor};
                if (j.type == JointType::Hinge)
                    anchors = {j.anchor - kHingeHalfSpan * j.axis, j.anchor + kHingeHalfSpan * j.axis};
                for (const glm::vec3& a : anchors) {
                    // The anchor is given in body1's frame; the world body's frame is the world.
                    const glm::vec3 local = w->bodyOf_[j.a] < 0 ? a : localAnchor(j.a, a);
                    x << "<connect body1=\"" << bodyName(j.a) << "\" body2=\"" << bodyName(j.b)
                      << "\" anchor=\"" << vec(local) << "\"/>\n";
                }
            }
            x << "</equality>\n<contact>\n";
            for (const JointDesc& j : scene.joints)
                x << "<exclude body1=\"" << bodyName(j.a) << "\" body2=\"" << bodyName(j.b) << "\"/>\n";
            x << "</contact>\n";
        }
        x << "</mujoco>\n";

        // MuJoCo 2.2 reads models from files.
        char path[] = "/tmp/rubble-mujoco-XXXXXX.xml";
        const int fd = mkstemps(path, 4);
        if (fd < 0) return makeError(ErrorKind::Io, path, "cannot create the model file");
        const std::string text = x.str();
        const bool written = write(fd, text.data(), text.size()) == ssize_t(text.size());
        close(fd);
        char error[1000] = "";
        w->model_ = written ? mj_loadXML(path, nullptr, error, sizeof error) : nullptr;
        unlink(path);
        if (!w->model_) {
            std::string why = std::string("MuJoCo refused the model: ") + error;
            if (why.find("mjData") != std::string::npos)
                why += " (MuJoCo 2.2 keeps dense arrays of njmax x njmax and njmax x nv; " +
                       std::to_string(w->dynamicCount_) + " free bodies are beyond it)";
            return makeError(ErrorKind::NotSupported, scene.file, why);
        }
        w->data_ = mj_makeData(w->model_);
        for (std::size_t i = 0; i < n; ++i) {
            const int b = w->bodyOf_[i];
            if (b < 0) continue;
            const int dof = w->model_->body_dofadr[b];
            const BodyDesc& d = scene.bodies[i];
            // Free joint velocities: linear in the world frame, angular in the body frame.
            const glm::vec3 wLocal = glm::conjugate(d.orientation) * d.angularVelocity;
            for (int k = 0; k < 3; ++k) {
                w->data_->qvel[dof + k] = d.linearVelocity[k];
                w->data_->qvel[dof + 3 + k] = wLocal[k];
            }
        }
        mj_forward(w->model_, w->data_);
        for (const BodyDesc& d : scene.bodies) w->names_.push_back(d.name);
        w->statics_ = scene.bodies;
        return std::unique_ptr<PeerWorld>(std::move(w));
    }

    ~MujocoWorld() override {
        if (data_) mj_deleteData(data_);
        if (model_) mj_deleteModel(model_);
    }

    void step() override { mj_step(model_, data_); }

    void read(std::vector<TrajectoryRow>& rows) const override {
        rows.resize(bodyOf_.size());
        for (std::size_t i = 0; i < bodyOf_.size(); ++i) {
            const int b = bodyOf_[i];
            if (b < 0) {
                rows[i] = TrajectoryRow{names_[i], statics_[i].position, statics_[i].orientation,
                                        glm::vec3(0.0f), glm::vec3(0.0f)};
                continue;
            }
            const mjtNum* p = data_->xpos + 3 * b;
            const mjtNum* q = data_->xquat + 4 * b;
            const int dof = model_->body_dofadr[b];
            const glm::quat orientation = glm::normalize(glm::quat(float(q[0]), float(q[1]), float(q[2]), float(q[3])));
            const glm::vec3 v(float(data_->qvel[dof]), float(data_->qvel[dof + 1]), float(data_->qvel[dof + 2]));
            const glm::vec3 wLocal(float(data_->qvel[dof + 3]), float(data_->qvel[dof + 4]),
                                   float(data_->qvel[dof + 5]));
            rows[i] = TrajectoryRow{names_[i], glm::vec3(float(p[0]), float(p[1]), float(p[2])),
                                    orientation, v, orientation * wLocal};
        }
    }

    std::vector<std::string> caveats() const override {
        return {"soft contacts (MuJoCo's default solref/solimp): no restitution coefficient",
                "joints as soft connect equalities (a hinge is two of them along its axis)",
                "friction combines as max(mu_a, mu_b) (rubble: sqrt(mu_a mu_b))",
                "pyramidal friction cone, PGS solver, no sleeping"};
    }

  private:
    MujocoWorld() = default;
    mjModel* model_ = nullptr;
    mjData* data_ = nullptr;
    std::vector<int> bodyOf_; // MuJoCo body id per scene body, -1 for static geoms
    std::size_t dynamicCount_ = 0;
    std::vector<std::string> names_;
    std::vector<BodyDesc> statics_;
};

} // namespace
} // namespace rubble::peers

int main(int argc, char** argv) {
    using namespace rubble;
    return peers::runPeer(argc, argv, "mujoco", mj_versionString(),
                          [](const Scene& scene, const std::vector<Shape>& shapes)
                              -> Result<std::unique_ptr<peers::PeerWorld>> {
                              return peers::MujocoWorld::create(scene, shapes);
                          });
}
