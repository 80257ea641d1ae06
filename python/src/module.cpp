// python/src/module.cpp: the extension module rubble._core: error translation, scene sources and
// keyword options shared by the World and the tools (world_bindings.cpp, tools_bindings.cpp).
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "python/src/bindings.h"
#include "rubble/version.h"

namespace rubble::python {
namespace {

const char* kindName(ErrorKind k) {
    switch (k) {
    case ErrorKind::BadInput: return "BadInput";
    case ErrorKind::NotSupported: return "NotSupported";
    case ErrorKind::Io: return "Io";
    case ErrorKind::Device: return "Device";
    case ErrorKind::Numerical: return "Numerical";
    case ErrorKind::Internal: return "Internal";
    }
    return "Internal";
}

// rubble._errors.raise_error builds the exception of the error's kind and sets it.
void translate(const ErrorException& e) {
    py::module_ errors = py::module_::import("rubble._errors");
    py::object exc = errors.attr("make_error")(kindName(e.error.kind), e.error.where,
                                               e.error.message, e.file);
    PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exc.ptr())), exc.ptr());
}

template <class T>
std::optional<T> numberOf(const py::handle& v) {
    if (py::isinstance<py::bool_>(v)) return std::nullopt;
    if constexpr (std::is_integral_v<T>) {
        if (!py::isinstance<py::int_>(v)) return std::nullopt;
        const long long n = v.cast<long long>();
        if (n < std::numeric_limits<T>::min() || n > std::numeric_limits<T>::max())
            return std::nullopt;
        return T(n);
    } else {
        if (!py::isinstance<py::int_>(v) && !py::isinstance<py::float_>(v)) return std::nullopt;
        return v.cast<T>();
    }
}

std::string textOf(const py::handle& v, const std::string& where) {
    if (!py::isinstance<py::str>(v)) badInput(where, "expected a string, got " + std::string(py::str(py::repr(v))));
    return v.cast<std::string>();
}

template <class E, class Parse>
E enumOf(const py::handle& v, const std::string& where, Parse parse, const char* choices) {
    const std::string text = textOf(v, where);
    const std::optional<E> e = parse(text);
    if (!e) badInput(where, "unknown value \"" + text + "\" (expected " + choices + ")");
    return *e;
}

} // namespace

void badInput(const std::string& where, const std::string& message) {
    throw ErrorException{makeError(ErrorKind::BadInput, where, message), {}};
}

std::string sceneLabel(const py::object& source, const std::string& label) {
    if (py::isinstance<py::dict>(source)) return label.empty() ? "<scene dict>" : label;
    return py::str(py::module_::import("os").attr("fspath")(source)).cast<std::string>();
}

Scene sceneFrom(const py::object& source, const std::string& baseDir, const std::string& label) {
    const std::string file = sceneLabel(source, label);
    if (py::isinstance<py::dict>(source)) {
        const std::string text =
            py::module_::import("json").attr("dumps")(source).cast<std::string>();
        Result<Scene> scene = parseScene(text, file, baseDir.empty() ? "." : baseDir);
        check(scene, file);
        return std::move(*scene);
    }
    Result<Scene> scene = loadScene(file);
    check(scene, file);
    return std::move(*scene);
}

void applyKeywords(const py::dict& keywords, const std::string& context, Scene& scene,
                   RunOptions& run) {
    SimulationOptions& sim = scene.simulation;
    for (const auto& [k, v] : keywords) {
        const std::string key = py::str(k).cast<std::string>();
        const std::string where = context + ": " + key;
        if (key == "steps") {
            const auto n = numberOf<int>(v);
            if (!n || *n < 0) badInput(where, "expected a whole number of 0 or more");
            sim.steps = *n;
        } else if (key == "dt") {
            const auto x = numberOf<float>(v);
            if (!x || !(*x > 0.0f) || !std::isfinite(*x))
                badInput(where, "expected a time step in s greater than 0");
            sim.dt = *x;
        } else if (key == "iterations") {
            const auto n = numberOf<int>(v);
            if (!n || *n < 1) badInput(where, "expected a whole number of 1 or more");
            sim.solver.iterations = *n;
        } else if (key == "particle_spacing" || key == "particle-spacing") {
            const auto x = numberOf<float>(v);
            if (!x || !(*x > 0.0f) || !std::isfinite(*x))
                badInput(where, "expected a length in m greater than 0");
            sim.collision.particleSpacing = *x;
        } else if (key == "backend") {
            sim.backend = enumOf<Backend>(v, where, parseBackend, "cpu or opencl");
        } else if (key == "integrator") {
            sim.integrator =
                enumOf<Integrator>(v, where, parseIntegrator, "symplectic or explicit");
        } else if (key == "solver") {
            sim.solver.type = enumOf<SolverType>(v, where, parseSolverType,
                                                 "pgs, jacobi, lcp-jacobi or lemke");
        } else if (key == "collision") {
            sim.collision.method =
                enumOf<CollisionMethod>(v, where, parseCollisionMethod, "sat or particles");
        } else if (key == "device") {
            run.device = py::isinstance<py::int_>(v) ? std::to_string(v.cast<long long>())
                                                      : textOf(v, where);
        } else if (key == "kernel_dir") {
            run.kernelDir = py::str(py::module_::import("os").attr("fspath")(v));
        } else if (key == "deterministic") {
            if (!py::isinstance<py::bool_>(v)) badInput(where, "expected True or False");
            run.deterministic = v.cast<bool>();
        } else {
            throw py::type_error(context + ": unknown option '" + key +
                                 "' (expected steps, dt, backend, integrator, solver, iterations, "
                                 "collision, particle_spacing, device, kernel_dir or "
                                 "deterministic)");
        }
    }
}

glm::vec3 vec3From(const py::handle& value, const char* what) {
    // ensure() gives an empty array, the Python error cleared, for what is not numeric.
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || a.size() != 3)
        throw py::value_error(std::string(what) + ": expected three numbers, got " +
                              std::string(py::str(py::repr(value))));
    const double* d = a.data();
    return glm::vec3(float(d[0]), float(d[1]), float(d[2]));
}

} // namespace rubble::python

PYBIND11_MODULE(_core, m) {
    namespace py = pybind11;
    using namespace rubble::python;
    m.doc() = "rubble's C++ library: worlds, comparisons, solvers and devices. Use the package "
              "rubble, which re-exports these with its own helpers.";
    m.attr("__version__") = rubble::kVersion;
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const ErrorException& e) {
            translate(e);
        }
    });
    bindWorld(m);
    bindTools(m);
}
