// python/src/tools_bindings.cpp: the tables of `rubble compare` and `rubble solvers`, and the
// OpenCL devices, as columns of NumPy arrays (the package turns them into tables).
#include <cmath>
#include <limits>
#include <vector>

#include <pybind11/stl.h>

#include "python/src/bindings.h"
#include "rubble/tools.h"

namespace rubble::python {
namespace {

template <class T> py::array_t<T> column(const std::vector<T>& v) {
    py::array_t<T> a(py::ssize_t(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

// The columns of `rubble compare --csv`, in its order.
py::dict compareColumns(const std::vector<CompareRow>& rows) {
    const std::size_t n = rows.size();
    std::vector<long long> step(n);
    std::vector<double> time(n), pmax(n), prms(n), amax(n), arms(n), kea(n), keb(n), pa(n),
        pb(n), la(n), lb(n), pena(n), penb(n), resa(n), resb(n);
    std::vector<std::uint32_t> ca(n), cb(n);
    for (std::size_t i = 0; i < n; ++i) {
        const CompareRow& r = rows[i];
        step[i] = r.step;
        time[i] = r.time;
        pmax[i] = r.positionMax;
        prms[i] = r.positionRms;
        amax[i] = r.angleMax;
        arms[i] = r.angleRms;
        kea[i] = r.a.kineticEnergy;
        keb[i] = r.b.kineticEnergy;
        pa[i] = r.a.linearMomentum;
        pb[i] = r.b.linearMomentum;
        la[i] = r.a.angularMomentum;
        lb[i] = r.b.angularMomentum;
        pena[i] = r.a.penetration;
        penb[i] = r.b.penetration;
        resa[i] = r.a.residual;
        resb[i] = r.b.residual;
        ca[i] = r.a.contacts;
        cb[i] = r.b.contacts;
    }
    py::dict d;
    d["step"] = column(step);
    d["time"] = column(time);
    d["position_max"] = column(pmax);
    d["position_rms"] = column(prms);
    d["angle_max"] = column(amax);
    d["angle_rms"] = column(arms);
    d["kinetic_energy_a"] = column(kea);
    d["kinetic_energy_b"] = column(keb);
    d["linear_momentum_a"] = column(pa);
    d["linear_momentum_b"] = column(pb);
    d["angular_momentum_a"] = column(la);
    d["angular_momentum_b"] = column(lb);
    d["largest_penetration_a"] = column(pena);
    d["largest_penetration_b"] = column(penb);
    d["residual_a"] = column(resa);
    d["residual_b"] = column(resb);
    d["contacts_a"] = column(ca);
    d["contacts_b"] = column(cb);
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
    d["iteration"] = column(iteration);
    d["residual"] = column(residual);
    d["complementarity"] = column(complementarity);
    d["velocity_error"] = column(velocityError);
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

} // namespace

void bindTools(py::module_& m) {
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
