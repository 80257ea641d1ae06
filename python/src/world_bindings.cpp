// python/src/world_bindings.cpp: rubble.World: a world built from a scene, stepped with the GIL
// released, its bodies read into NumPy arrays in one pass, and changed at run time.
#include <atomic>
#include <chrono>
#include <memory>
#include <vector>

#include <pybind11/stl.h>

#include "python/src/bindings.h"
#include "rubble/world.h"

namespace rubble::python {
namespace {

// One contact record as NumPy sees it (World.contacts' structured dtype).
struct ContactRow {
    std::uint32_t a, b;
    float point[3];
    float normal[3];
    float depth;
};

// The Python object: the world, the file it came from, and whether a thread is using it.
struct PyWorld {
    std::unique_ptr<World> world;
    std::string file;
    std::atomic<bool> busy{false};
};

// Marks a world in use for a call; a second thread's call raises instead of racing the first.
class InUse {
  public:
    explicit InUse(PyWorld& w) : w_(w) {
        if (w_.busy.exchange(true))
            throw std::runtime_error("rubble.World: another thread is using this world (one "
                                     "thread at a time may call a world)");
    }
    ~InUse() { w_.busy = false; }
    InUse(const InUse&) = delete;
    InUse& operator=(const InUse&) = delete;

  private:
    PyWorld& w_;
};

// A body by index (negative counts from the end, as Python's) or by name.
std::uint32_t bodyIndex(const PyWorld& w, const py::handle& body) {
    const long long n = w.world->bodyCount();
    if (py::isinstance<py::str>(body)) {
        const std::string name = body.cast<std::string>();
        const std::optional<std::uint32_t> i = w.world->findBody(name);
        if (!i) throw py::key_error("no body named '" + name + "'");
        return *i;
    }
    if (!py::isinstance<py::int_>(body) || py::isinstance<py::bool_>(body))
        throw py::type_error("a body is an index or a name");
    long long i = body.cast<long long>();
    if (i < 0) i += n;
    if (i < 0 || i >= n)
        throw py::index_error("body " + std::to_string(body.cast<long long>()) +
                              " is out of range (the world has " + std::to_string(n) +
                              " bodies)");
    return std::uint32_t(i);
}

using ReadFn = Status (World::*)(std::uint32_t, std::span<float>) const;

// A (bodies x width) float32 array filled by one of World's bulk reads.
py::array_t<float> readArray(PyWorld& w, ReadFn read, py::ssize_t width) {
    InUse use(w);
    const py::ssize_t n = w.world->bodyCount();
    py::array_t<float> out({n, width});
    check(((*w.world).*read)(0, std::span<float>(out.mutable_data(), std::size_t(n * width))));
    return out;
}

// Steps n times with the GIL released, coming back every tenth of a second for Ctrl-C.
void stepWorld(PyWorld& w, long long n) {
    if (n < 0) throw py::value_error("step: n must be 0 or more, got " + std::to_string(n));
    InUse use(w);
    long long done = 0;
    while (done < n) {
        Status s;
        {
            py::gil_scoped_release release;
            const auto start = std::chrono::steady_clock::now();
            while (done < n && s.ok()) {
                s = w.world->step();
                if (s.ok()) ++done;
                if (std::chrono::steady_clock::now() - start > std::chrono::milliseconds(100))
                    break;
            }
        }
        check(s);
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
}

std::vector<DebrisPiece> debrisPieces(const PyWorld& w, const std::string& shape,
                                      const py::handle& positions, float mass,
                                      const std::string& material, const py::handle& orientations,
                                      const py::handle& velocities,
                                      const py::handle& angularVelocities,
                                      const std::string& name) {
    const std::optional<std::uint32_t> s = w.world->findShape(shape);
    if (!s) throw py::key_error("the scene has no shape named '" + shape + "'");
    const std::optional<std::uint32_t> mat = w.world->findMaterial(material);
    if (!mat) throw py::key_error("the scene has no material named '" + material + "'");
    using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;
    auto rows = [](const py::handle& h, py::ssize_t width, py::ssize_t count, const char* what) {
        const Rows a = Rows::ensure(h);
        if (!a || a.ndim() != 2 || a.shape(1) != width || (count >= 0 && a.shape(0) != count))
            throw py::value_error(std::string("add_debris: ") + what + " must be an array of " +
                                  (count >= 0 ? std::to_string(count) : std::string("N")) +
                                  " rows of " + std::to_string(width) + " numbers");
        return a;
    };
    const Rows x = rows(positions, 3, -1, "positions");
    const py::ssize_t n = x.shape(0);
    std::vector<DebrisPiece> pieces(static_cast<std::size_t>(n));
    for (py::ssize_t i = 0; i < n; ++i) {
        DebrisPiece& d = pieces[std::size_t(i)];
        d.name = name + std::to_string(i);
        d.shape = *s;
        d.material = *mat;
        d.mass = mass;
        d.position = glm::vec3(float(x.at(i, 0)), float(x.at(i, 1)), float(x.at(i, 2)));
    }
    if (!orientations.is_none()) {
        const Rows q = rows(orientations, 4, n, "orientations");
        for (py::ssize_t i = 0; i < n; ++i)
            pieces[std::size_t(i)].orientation = glm::normalize(
                glm::quat(float(q.at(i, 0)), float(q.at(i, 1)), float(q.at(i, 2)),
                          float(q.at(i, 3))));
    }
    for (auto [h, field, what] :
         {std::tuple{velocities, &DebrisPiece::linearVelocity, "velocities"},
          std::tuple{angularVelocities, &DebrisPiece::angularVelocity, "angular_velocities"}}) {
        if (h.is_none()) continue;
        const Rows v = rows(h, 3, n, what);
        for (py::ssize_t i = 0; i < n; ++i)
            pieces[std::size_t(i)].*field =
                glm::vec3(float(v.at(i, 0)), float(v.at(i, 1)), float(v.at(i, 2)));
    }
    return pieces;
}

py::tuple tuple3(const glm::dvec3& v) { return py::make_tuple(v.x, v.y, v.z); }

py::dict metricsDict(const WorldMetrics& m) {
    py::dict d;
    d["time"] = m.time;
    d["step"] = m.step;
    d["bodies"] = m.bodies;
    d["dynamic_bodies"] = m.dynamicBodies;
    d["asleep_bodies"] = m.asleepBodies;
    d["kinetic_energy"] = m.kineticEnergy;
    d["potential_energy"] = m.potentialEnergy;
    d["linear_momentum"] = tuple3(m.linearMomentum);
    d["angular_momentum"] = tuple3(m.angularMomentum);
    d["max_speed"] = m.maxSpeed;
    d["centre_of_mass"] = tuple3(m.centreOfMass);
    d["lo"] = tuple3(glm::dvec3(m.lo));
    d["hi"] = tuple3(glm::dvec3(m.hi));
    d["contacts"] = m.contacts;
    d["largest_penetration"] = double(m.largestPenetration);
    d["solver_residual"] = double(m.solverResidual);
    d["step_ms"] = m.stepMs;
    return d;
}

py::dict optionsDict(const SimulationOptions& o) {
    py::dict d;
    d["dt"] = double(o.dt);
    d["steps"] = o.steps;
    d["gravity"] = tuple3(glm::dvec3(o.gravity));
    d["integrator"] = std::string(toString(o.integrator));
    d["backend"] = std::string(toString(o.backend));
    d["collision"] = std::string(toString(o.collisionMethod()));
    d["particle_spacing"] = double(o.collision.particleSpacing);
    d["solver"] = std::string(toString(o.solverType()));
    d["iterations"] = o.solver.iterations;
    d["coupling"] = std::string(toString(o.coupling));
    return d;
}

const char* kLoadDoc = R"(Builds a world from a scene.

scene: a path to a scene file (str or os.PathLike) or a dict in the scene format
    (docs/scene-format.md).
base_dir: where a dict's mesh files are found (default: the working directory).
label: the name a dict scene's errors give its file (default "<scene dict>").
**options: the command line's options: steps, dt, backend ("cpu" or "opencl"), integrator,
    solver ("pgs", "jacobi", "lcp-jacobi", "lemke", "soft-step"), iterations, collision ("sat" or
    "particles"), particle_spacing, device (index or name fragment), kernel_dir, deterministic.

Raises rubble.SceneError naming the file and the field (or the option) for bad input,
rubble.NotSupportedError, rubble.DeviceError for OpenCL failures, TypeError for an unknown
option.)";

} // namespace

void bindWorld(py::module_& m) {
    PYBIND11_NUMPY_DTYPE(ContactRow, a, b, point, normal, depth);
    py::class_<PyWorld> w(m, "World", R"(A simulated world. Build one with World.load; one thread
at a time may use it. Arrays are float32, one row per body in scene order.)");
    w.def_static(
        "load",
        [](const py::object& scene, const std::string& baseDir, const std::string& label,
           const py::kwargs& options) {
            const std::string file = sceneLabel(scene, label);
            Scene s = sceneFrom(scene, baseDir, label);
            RunOptions run;
            applyKeywords(options, "World.load", s, run);
            auto out = std::make_unique<PyWorld>();
            out->file = file;
            Result<World> world = [&] {
                py::gil_scoped_release release;
                return World::create(s, run);
            }();
            check(world, file);
            out->world = std::make_unique<World>(std::move(*world));
            return out;
        },
        py::arg("scene"), py::kw_only(), py::arg("base_dir") = "", py::arg("label") = "",
        kLoadDoc);
    w.def("step", &stepWorld, py::arg("n") = 1,
          "Advances n steps of dt with the GIL released. Raises rubble.NumericalError naming "
          "the body and the step when the simulation blows up (a non-finite state, energy "
          "growth, a joint apart; the world is then past use), rubble.LimitError when a step "
          "needs more pairs or contacts than rubble allows, "
          "rubble.DeviceError for OpenCL failures.");
    w.def_property_readonly("time", [](PyWorld& s) { return s.world->time(); },
                            "Simulated time, s.");
    w.def_property_readonly("step_count", [](PyWorld& s) { return s.world->stepIndex(); },
                            "Steps taken so far.");
    w.def_property_readonly("dt", [](PyWorld& s) { return double(s.world->options().dt); },
                            "The time step, s.");
    w.def_property_readonly("options", [](PyWorld& s) { return optionsDict(s.world->options()); },
                            "The simulation options in effect, as a dict.");
    w.def_property_readonly("scene_name", [](PyWorld& s) { return s.world->sceneName(); });
    w.def_property_readonly(
        "warnings",
        [](PyWorld& s) {
            std::vector<std::string> out;
            for (const Warning& warning : s.world->warnings()) out.push_back(warning.describe());
            return out;
        },
        "What the scene asks past rubble's promises, found at load (for now: dynamic bodies "
        "whose masses differ more than 1:100), each as 'file: bodies: message'; the world runs "
        "anyway.");
    w.def_property_readonly("device_name", [](PyWorld& s) { return s.world->deviceName(); },
                            "The OpenCL device's name, or \"cpu\".");
    w.def("__len__", [](PyWorld& s) { return s.world->bodyCount(); }, "The number of bodies.");
    w.def_property_readonly("body_count", [](PyWorld& s) { return s.world->bodyCount(); });
    w.def_property_readonly(
        "names",
        [](PyWorld& s) {
            std::vector<std::string> out(s.world->bodyCount());
            for (std::uint32_t i = 0; i < out.size(); ++i) out[i] = s.world->bodyName(i);
            return out;
        },
        "Body names, in index order.");
    w.def(
        "find_body",
        [](PyWorld& s, const std::string& name) { return s.world->findBody(name); },
        py::arg("name"), "The index of the body with that name, or None.");
    w.def_property_readonly(
        "positions", [](PyWorld& s) { return readArray(s, &World::readPositions, 3); },
        "Centres of mass, world frame, m: an (N, 3) float32 array (a new array per read).");
    w.def_property_readonly(
        "orientations", [](PyWorld& s) { return readArray(s, &World::readOrientations, 4); },
        "Orientations, body to world, as unit quaternions w, x, y, z: an (N, 4) float32 array.");
    w.def_property_readonly(
        "velocities", [](PyWorld& s) { return readArray(s, &World::readLinearVelocities, 3); },
        "Linear velocities of the centres of mass, world frame, m/s: (N, 3) float32.");
    w.def_property_readonly(
        "angular_velocities",
        [](PyWorld& s) { return readArray(s, &World::readAngularVelocities, 3); },
        "Angular velocities, world frame, rad/s: (N, 3) float32.");
    w.def(
        "set_velocity",
        [](PyWorld& s, const py::handle& body, const py::handle& v, const py::handle& omega) {
            InUse use(s);
            const std::uint32_t i = bodyIndex(s, body);
            const glm::vec3 angular =
                omega.is_none() ? s.world->body(i).angularVelocity : vec3From(omega, "angular");
            check(s.world->setVelocity(i, vec3From(v, "velocity"), angular));
        },
        py::arg("body"), py::arg("velocity"), py::arg("angular") = py::none(),
        "Sets a dynamic or kinematic body's linear velocity (m/s, world) and, when given, its "
        "angular velocity (rad/s, world); wakes it. body is an index or a name. Raises "
        "rubble.SceneError for a static body.");
    w.def(
        "set_kinematic_target",
        [](PyWorld& s, const py::handle& body, const py::handle& position,
           const py::handle& orientation) {
            InUse use(s);
            const std::uint32_t i = bodyIndex(s, body);
            glm::quat q = s.world->body(i).orientation;
            if (!orientation.is_none()) {
                const auto a =
                    py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
                        orientation);
                if (!a || a.size() != 4)
                    throw py::value_error("orientation: expected four numbers w, x, y, z, got " +
                                          std::string(py::str(py::repr(orientation))));
                const double* d = a.data();
                q = glm::quat(float(d[0]), float(d[1]), float(d[2]), float(d[3]));
            }
            check(s.world->setKinematicTarget(i, vec3From(position, "position"), q));
        },
        py::arg("body"), py::arg("position"), py::arg("orientation") = py::none(),
        "Moves a kinematic body to a pose over the next step: position of its centre of mass "
        "(m, world) and, when given, orientation (w, x, y, z; default: the one it has). Its "
        "velocities become those that reach the pose in one step, and it keeps them afterwards. "
        "body is an index or a name. Raises rubble.SceneError for a body that is not kinematic.");
    w.def(
        "apply_impulse",
        [](PyWorld& s, const py::handle& body, const py::handle& impulse, const py::handle& at) {
            InUse use(s);
            const std::uint32_t i = bodyIndex(s, body);
            const glm::vec3 point = at.is_none() ? s.world->body(i).position : vec3From(at, "point");
            s.world->applyImpulse(i, vec3From(impulse, "impulse"), point);
        },
        py::arg("body"), py::arg("impulse"), py::arg("point") = py::none(),
        "Applies an impulse (N s, world) at a world point (m; default the centre of mass) now, "
        "and wakes the body. A static body is left alone.");
    w.def(
        "add_force",
        [](PyWorld& s, const py::handle& body, const py::handle& force, const py::handle& at) {
            InUse use(s);
            const std::uint32_t i = bodyIndex(s, body);
            if (at.is_none()) s.world->addForce(i, vec3From(force, "force"));
            else s.world->addForceAtPoint(i, vec3From(force, "force"), vec3From(at, "point"));
        },
        py::arg("body"), py::arg("force"), py::arg("point") = py::none(),
        "Adds a force (N, world) at a world point (default the centre of mass) for the next "
        "step only.");
    w.def(
        "add_debris",
        [](PyWorld& s, const std::string& shape, const py::handle& positions, float mass,
           const std::string& material, const py::handle& orientations,
           const py::handle& velocities, const py::handle& angularVelocities,
           const std::string& name) {
            InUse use(s);
            const std::vector<DebrisPiece> pieces =
                debrisPieces(s, shape, positions, mass, material, orientations, velocities,
                             angularVelocities, name);
            Result<std::uint32_t> first = [&] {
                py::gil_scoped_release release;
                return s.world->addDebris(pieces);
            }();
            check(first);
            return *first;
        },
        py::arg("shape"), py::arg("positions"), py::kw_only(), py::arg("mass") = 1.0f,
        py::arg("material") = "default", py::arg("orientations") = py::none(),
        py::arg("velocities") = py::none(), py::arg("angular_velocities") = py::none(),
        py::arg("name") = "debris",
        "Adds pieces of debris of a scene shape (by name), one per row of positions (N, 3; m), "
        "each of `mass` kg, and returns the index of the first. orientations (N, 4; w, x, y, z), "
        "velocities and angular_velocities (N, 3) are optional; pieces are named name0, name1, "
        "... On the opencl backend they join the device's bodies. Raises KeyError for an "
        "unknown shape or material, rubble.SceneError for a plane or a mass that is not > 0.");
    w.def(
        "remove_debris_outside",
        [](PyWorld& s, const py::handle& lo, const py::handle& hi) {
            InUse use(s);
            Result<std::uint32_t> removed =
                s.world->removeDebrisOutside(vec3From(lo, "lo"), vec3From(hi, "hi"));
            check(removed);
            return *removed;
        },
        py::arg("lo"), py::arg("hi"),
        "Removes the debris whose centre of mass is outside the box [lo, hi] (m) and returns "
        "how many went; later bodies' indices go down.");
    w.def(
        "explode",
        [](PyWorld& s, const py::handle& centre, float impulse, float radius) {
            InUse use(s);
            check(s.world->explode(vec3From(centre, "centre"), impulse, radius));
        },
        py::arg("centre"), py::arg("impulse"), py::arg("radius"),
        "Adds an explosion at the start of the next step: every dynamic body within radius (m) "
        "of centre gets impulse * (1 - d / radius) N s away from it, and wakes.");
    w.def(
        "contacts",
        [](PyWorld& s) {
            InUse use(s);
            const std::vector<ContactInfo> c = s.world->contacts();
            py::array_t<ContactRow> out(py::ssize_t(c.size()));
            ContactRow* rows = out.mutable_data();
            for (std::size_t k = 0; k < c.size(); ++k)
                rows[k] = ContactRow{c[k].a,
                                     c[k].b,
                                     {c[k].position.x, c[k].position.y, c[k].position.z},
                                     {c[k].normal.x, c[k].normal.y, c[k].normal.z},
                                     c[k].depth};
            return out;
        },
        "The last step's contact points found on the host, as a structured array with fields "
        "a, b (body indices; the normal points from a to b), point (3, m), normal (3) and depth "
        "(m, negative for a gap). The device's own contacts on the opencl backend are not read "
        "back (see metrics()['contacts']).");
    w.def(
        "metrics",
        [](PyWorld& s) {
            InUse use(s);
            return metricsDict(s.world->metrics());
        },
        "The world summed up now, as a dict: time, step, bodies, dynamic_bodies, asleep_bodies, "
        "kinetic_energy and potential_energy (J), linear_momentum and angular_momentum (about "
        "the origin), max_speed (m/s), centre_of_mass, lo and hi (the box around the centres of "
        "mass), and the last step's contacts, largest_penetration (m), solver_residual (N s) and "
        "step_ms.");
    w.def("__repr__", [](PyWorld& s) {
        return "<rubble.World '" + s.world->sceneName() + "': " +
               std::to_string(s.world->bodyCount()) + " bodies, step " +
               std::to_string(s.world->stepIndex()) + ", " + s.world->deviceName() + ">";
    });
}

} // namespace rubble::python
