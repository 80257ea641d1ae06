// python/src/module.cpp: the extension module rubble._core: error translation, scene sources and
// keyword options shared by the World and the tools (world_bindings.cpp, tools_bindings.cpp).
#include <algorithm>
#include <iterator>
#include <span>
#include <string_view>

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
    case ErrorKind::Limit: return "Limit";
    case ErrorKind::Interrupted: return "Interrupted";
    case ErrorKind::Internal: return "Internal";
    }
    return "Internal";
}

// rubble._errors.make_error builds the exception of the error's kind; it is raised here.
void translate(const ErrorException& e) {
    py::module_ errors = py::module_::import("rubble._errors");
    py::object exc = errors.attr("make_error")(kindName(e.error.kind), e.error.where,
                                               e.error.message, e.file);
    PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(exc.ptr())), exc.ptr());
}

// The keywords that World.load, compare and solvers take: the command line's options, spelt
// with underscores (rubble._core.OPTION_KEYS, which the sweeps read).
constexpr std::string_view kKeywords[] = {"steps",      "dt",         "backend",
                                          "integrator", "solver",     "iterations",
                                          "collision",  "particle_spacing", "sleep",
                                          "device",     "kernel_dir", "deterministic"};

// A keyword's value as the command line would write it, for the option table to read and check
// (so that a keyword is refused exactly where a flag would be): True/False as true/false, an int
// in full, a float as its shortest repr, a path as its text.
std::string optionTextOf(const py::handle& v, const std::string& where) {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    // Python's and NumPy's integers, then anything that is a float.
    const auto object = py::reinterpret_borrow<py::object>(v);
    if (py::hasattr(v, "__index__")) return py::str(py::int_(object)).cast<std::string>();
    if (py::hasattr(v, "__float__"))
        return py::str(py::repr(py::float_(object))).cast<std::string>();
    if (py::hasattr(v, "__fspath__"))
        return py::str(py::module_::import("os").attr("fspath")(v)).cast<std::string>();
    badInput(where, "expected a number, a string or True/False, got " +
                        std::string(py::str(py::repr(v))));
}

// kKeywords as a Python tuple.
// A list of names as a tuple of str.
py::tuple tupleOf(std::span<const std::string_view> names) {
    py::tuple keys(names.size());
    for (std::size_t i = 0; i < names.size(); ++i)
        keys[i] = py::str(names[i].data(), names[i].size());
    return keys;
}

// kKeywords in words: "steps, dt, ..., kernel_dir or deterministic".
std::string keywordList() {
    std::string out;
    for (std::size_t i = 0; i < std::size(kKeywords); ++i) {
        if (i > 0) out += i + 1 == std::size(kKeywords) ? " or " : ", ";
        out += kKeywords[i];
    }
    return out;
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
    for (const auto& [k, v] : keywords) {
        std::string key = py::str(k).cast<std::string>();
        const std::string where = context + ": " + key;
        std::replace(key.begin(), key.end(), '-', '_'); // particle-spacing as before
        if (std::find(std::begin(kKeywords), std::end(kKeywords), key) == std::end(kKeywords))
            throw py::type_error(context + ": unknown option '" + py::str(k).cast<std::string>() +
                                 "' (expected " + keywordList() + ")");
        std::string name = key;
        std::replace(name.begin(), name.end(), '_', '-');
        check(setOptionText(name, optionTextOf(v, where), where, scene.simulation, run));
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
    m.attr("OPTION_KEYS") = tupleOf(kKeywords);
    m.attr("SCENE_KEYS") = tupleOf(rubble::kSceneKeys);
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
