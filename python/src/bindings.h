// python/src/bindings.h: what the parts of the module rubble._core share: rubble's errors as
// Python exceptions, scenes from a path or a dict, keyword options, vectors from Python.
#pragma once

#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"

namespace rubble::python {

namespace py = pybind11;

/// A rubble Error on its way to Python; the translator in module.cpp raises the exception class
/// of its kind (rubble/_errors.py). `file` is the scene file or label that was being read, so
/// that the exception can tell the file from the field.
struct ErrorException {
    Error error;
    std::string file;
};

/// Raises the error of a failed Status or Result.
template <class R> void check(const R& r, const std::string& file = {}) {
    if (!r.ok()) throw ErrorException{r.error(), file};
}

/// Raises a BadInput error (rubble.SceneError) at `where`.
[[noreturn]] void badInput(const std::string& where, const std::string& message);

/// A scene from a path (str or os.PathLike) or a dict in the scene format; a dict's mesh paths
/// resolve against `baseDir` (the working directory when empty) and its errors name `label`.
Scene sceneFrom(const py::object& source, const std::string& baseDir, const std::string& label);

/// The name a scene's errors give its file: the path, or the dict's label.
std::string sceneLabel(const py::object& source, const std::string& label);

/// Applies the command line's options given as keywords (steps, dt, backend, integrator,
/// solver, iterations, collision, particle_spacing, device, kernel_dir, deterministic) to a
/// scene and a run. Unknown keys raise TypeError; bad values rubble.SceneError at
/// `context: key`.
void applyKeywords(const py::dict& keywords, const std::string& context, Scene& scene,
                   RunOptions& run);

/// Three numbers from any sequence or array; ValueError naming `what` otherwise.
glm::vec3 vec3From(const py::handle& value, const char* what);

/// Registers the World class (world_bindings.cpp).
void bindWorld(py::module_& m);
/// Registers compare, solvers and devices (tools_bindings.cpp).
void bindTools(py::module_& m);

} // namespace rubble::python
