// python/src/tools_bindings.cpp: the tables of `rubble compare` and `rubble solvers`, and the
// OpenCL devices, as columns of NumPy arrays (the package turns them into tables).
#include <functional>
#include <limits>
#include <type_traits>
#include <vector>

#include <pybind11/stl.h>

#include "python/src/bindings.h"
#include "rubble/tools.h"

namespace rubble::python {
namespace {

// A column from a vector (pybind11 copies the data once).
template <class T> py::array_t<T> array(const std::vector<T>& v) {
    return py::array_t<T>(py::ssize_t(v.size()), v.data());
}

// A column of one value per row (a member or a function of the row), written straight into
// the array; `T` is the column's dtype.
template <class T, class Row, class Get>
py::array_t<T> column(const std::vector<Row>& rows, Get get) {
    py::array_t<T> a(py::ssize_t(rows.size()));
    T* out = a.mutable_data();
    for (const Row& r : rows) *out++ = T(std::invoke(get, r));
    return a;
}

// The columns of `rubble compare --csv`, in its order; each side's sample field is two columns,
// name_a and name_b, its float fields as float64.
py::dict compareColumns(const std::vector<CompareRow>& rows) {
    py::dict d;
    auto sides = [&]<class T>(const std::string& name, T CompareSample::*field) {
        using Out = std::conditional_t<std::is_same_v<T, float>, double, T>;
        d[py::str(name + "_a")] =
            column<Out>(rows, [=](const CompareRow& r) { return r.a.*field; });
        d[py::str(name + "_b")] =
            column<Out>(rows, [=](const CompareRow& r) { return r.b.*field; });
    };
    d["step"] = column<long long>(rows, &CompareRow::step);
    d["time"] = column<double>(rows, &CompareRow::time);
    d["position_max"] = column<double>(rows, &CompareRow::positionMax);
    d["position_rms"] = column<double>(rows, &CompareRow::positionRms);
    d["angle_max"] = column<double>(rows, &CompareRow::angleMax);
    d["angle_rms"] = column<double>(rows, &CompareRow::angleRms);
    sides("kinetic_energy", &CompareSample::kineticEnergy);
    sides("linear_momentum", &CompareSample::linearMomentum);
    sides("angular_momentum", &CompareSample::angularMomentum);
    sides("largest_penetration", &CompareSample::penetration);
    sides("residual", &CompareSample::residual);
    sides("contacts", &CompareSample::contacts);
    return d;
}

// The rows of `rubble solvers --csv`: one per solver, backend and iteration, lemke's last
// with its pivot count as the iteration; a missing velocity error is NaN.
py::dict solverColumns(const SolversTable& t) {
    std::vector<std::string> solver, backend;
    std::vector<long long> iteration;
    std::vector<double> residual, complementarity, velocityError;
    auto add = [&](const std::string& s, const std::string& b, long long k,
                   const SolverIterate& e) {
        solver.push_back(s);
        backend.push_back(b);
        iteration.push_back(k);
        residual.push_back(e.residual);
        complementarity.push_back(e.complementarity);
        velocityError.push_back(e.velocityError ? *e.velocityError
                                                : std::numeric_limits<double>::quiet_NaN());
    };
    for (const SolverHistory& h : t.histories)
        for (std::size_t k = 0; k < h.iterates.size(); ++k)
            add(h.solver, h.backend, (long long)(k + 1), h.iterates[k]);
    if (t.lemkePivots) {
        SolverIterate lemke = t.lemke;
        lemke.velocityError = 0.0; // the reference itself
        add("lemke", "cpu", *t.lemkePivots, lemke);
    }
    py::dict d;
    d["solver"] = py::array(py::cast(solver));
    d["backend"] = py::array(py::cast(backend));
    d["iteration"] = array(iteration);
    d["residual"] = array(residual);
    d["complementarity"] = array(complementarity);
    d["velocity_error"] = array(velocityError);
    return d;
}

py::dict solverInfo(const SolversTable& t) {
    py::dict skipped;
    for (const SolverHistory& h : t.histories)
        if (!h.skipped.empty()) skipped[py::str(h.solver + "/" + h.backend)] = h.skipped;
    if (!t.lemkePivots) skipped["lemke/cpu"] = t.lemkeSkipped;
    py::dict info;
    info["collision"] = t.collision;
    info["contacts"] = t.contacts;
    info["rows"] = t.rows;
    info["frictionless"] = t.frictionless;
    info["skipped"] = skipped;
    return info;
}

// The rows of `rubble solvers --suite --csv`, in its column order.
py::dict suiteColumns(const std::vector<SuiteRow>& rows) {
    auto text = [&](std::string SuiteRow::*field) {
        std::vector<std::string> v;
        for (const SuiteRow& r : rows) v.push_back(r.*field);
        return py::array(py::cast(v));
    };
    py::dict d;
    d["scene"] = text(&SuiteRow::scene);
    d["solver"] = text(&SuiteRow::solver);
    d["path"] = text(&SuiteRow::path);
    d["settings"] = text(&SuiteRow::settings);
    d["steps"] = column<long long>(rows, &SuiteRow::steps);
    d["stands"] = text(&SuiteRow::stands);
    d["top_drift"] = column<double>(rows, &SuiteRow::topDrift);
    d["top_creep"] = column<double>(rows, &SuiteRow::topCreep);
    d["penetration"] = column<double>(rows, &SuiteRow::penetration);
    d["energy_gained"] = column<double>(rows, &SuiteRow::energyGained);
    d["joint_error"] = column<double>(rows, &SuiteRow::jointError);
    d["ms_per_step"] = column<double>(rows, &SuiteRow::msPerStep);
    d["skipped"] = text(&SuiteRow::skipped);
    return d;
}

} // namespace

void bindTools(py::module_& m) {
    m.def(
        "solver_suite",
        [](const std::vector<std::string>& scenes, int steps, int passes, int relax,
           const std::vector<std::string>& paths, const py::dict& options) {
            SuiteOptions o;
            o.scenes = scenes;
            o.steps = steps;
            o.passes = passes;
            o.relax = relax;
            o.paths = paths;
            Scene unused;
            applyKeywords(options, "solver_suite", unused, o.run);
            Result<std::vector<SuiteRow>> rows = [&] {
                py::gil_scoped_release release;
                return runSolverSuite(o);
            }();
            check(rows, "solver_suite");
            return suiteColumns(*rows);
        },
        py::arg("scenes"), py::arg("steps"), py::arg("passes"), py::arg("relax"),
        py::arg("paths"), py::arg("options"),
        "The rows of `rubble solvers --suite --csv` for these scene files.");
    m.def(
        "compare",
        [](const py::object& scene, const py::dict& a, const py::dict& b, int steps,
           const std::string& baseDir, const std::string& label) {
            if (steps < 1) badInput("compare: steps", "must be 1 or more");
            const std::string file = sceneLabel(scene, label);
            const Scene base = sceneFrom(scene, baseDir, label);
            Scene sceneA = base, sceneB = base;
            RunOptions runA, runB;
            applyKeywords(a, "compare: a", sceneA, runA);
            applyKeywords(b, "compare: b", sceneB, runB);
            std::vector<CompareRow> rows;
            Status failed;
            {
                py::gil_scoped_release release;
                Result<Comparison> c = Comparison::create(sceneA, runA, sceneB, runB);
                if (!c) failed = c.status();
                for (int step = 0; c && failed.ok() && step <= steps; ++step) {
                    Result<CompareRow> row = c->next();
                    if (!row) failed = row.status();
                    else rows.push_back(*row);
                }
            }
            check(failed, file);
            return compareColumns(rows);
        },
        py::arg("scene"), py::arg("a"), py::arg("b"), py::arg("steps"), py::kw_only(),
        py::arg("base_dir") = "", py::arg("label") = "",
        "The columns of `rubble compare --csv` for a scene run on two sets of options.");
    m.def(
        "solvers",
        [](const py::object& scene, int step, int iterations, const py::dict& options,
           bool frictionless, const std::string& baseDir, const std::string& label) {
            const std::string file = sceneLabel(scene, label);
            Scene s = sceneFrom(scene, baseDir, label);
            RunOptions run;
            applyKeywords(options, "solvers", s, run);
            Result<SolversTable> table = [&] {
                py::gil_scoped_release release;
                return compareSolvers(s, run, step, iterations, frictionless);
            }();
            check(table, file);
            return py::make_tuple(solverColumns(*table), solverInfo(*table));
        },
        py::arg("scene"), py::arg("step"), py::arg("iterations"), py::arg("options"),
        py::arg("frictionless"), py::kw_only(), py::arg("base_dir") = "", py::arg("label") = "",
        "The rows of `rubble solvers --csv` and what the command prints around them.");
    m.def(
        "check_scene",
        [](const py::object& scene, const py::dict& options, const std::string& baseDir,
           const std::string& label) {
            Scene s = sceneFrom(scene, baseDir, label);
            RunOptions run;
            applyKeywords(options, "options", s, run);
            py::dict d;
            d["name"] = s.name;
            d["bodies"] = s.bodies.size();
            d["shapes"] = s.shapes.size();
            d["joints"] = s.joints.size();
            d["events"] = s.events.size();
            d["steps"] = s.simulation.steps;
            return d;
        },
        py::arg("scene"), py::arg("options"), py::kw_only(), py::arg("base_dir") = "",
        py::arg("label") = "",
        "Reads and checks a scene and options without building a world; a summary dict.");
    m.def(
        "devices",
        [] {
            Result<std::vector<DeviceDesc>> devices = openClDevices();
            check(devices);
            py::list out;
            for (const DeviceDesc& d : *devices) {
                py::dict e;
                e["index"] = d.index;
                e["platform"] = d.platform;
                e["name"] = d.name;
                e["version"] = d.version;
                e["driver"] = d.driver;
                e["compute_units"] = d.computeUnits;
                e["global_memory"] = d.globalMemory;
                e["max_allocation"] = d.maxAllocation;
                out.append(e);
            }
            return out;
        },
        "The OpenCL devices of every platform, as dicts.");
}

} // namespace rubble::python
