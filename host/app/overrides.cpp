// host/app/overrides.cpp: command-line overrides of scene fields, and error reporting.
#include <cstdio>

#include "host/app/commands.h"

namespace rubble::app {
namespace {

template <class E, class Parse>
Status overrideEnum(const std::optional<std::string>& value, const char* option, Parse parse,
                    const char* choices, E& out) {
    if (!value) return {};
    const std::optional<E> v = parse(*value);
    if (!v)
        return makeError(ErrorKind::BadInput, option,
                         "unknown value \"" + *value + "\" (expected " + choices + ")");
    out = *v;
    return {};
}

} // namespace

Status applyOverrides(const Overrides& o, Scene& scene) {
    SimulationOptions& sim = scene.simulation;
    if (o.steps) {
        if (*o.steps < 0) return makeError(ErrorKind::BadInput, "--steps", "must be 0 or more");
        sim.steps = *o.steps;
    }
    if (o.dt) {
        if (!(*o.dt > 0.0f) || !std::isfinite(*o.dt))
            return makeError(ErrorKind::BadInput, "--dt", "must be a finite number greater than 0");
        if (!std::isnormal(*o.dt))
            return makeError(ErrorKind::BadInput, "--dt",
                             "is too small for single precision (below 1.2e-38 s)");
        sim.dt = *o.dt;
    }
    if (o.iterations) {
        if (*o.iterations < 1) return makeError(ErrorKind::BadInput, "--iterations", "must be 1 or more");
        sim.solver.iterations = *o.iterations;
    }
    if (o.particleSpacing) {
        if (!(*o.particleSpacing >= float(kMinLength) && *o.particleSpacing <= float(kMaxLength)))
            return makeError(ErrorKind::BadInput, "--particle-spacing",
                             "must be between 0.0001 and 100000 m");
        sim.collision.particleSpacing = *o.particleSpacing;
    }
    RUBBLE_TRY(overrideEnum(o.backend, "--backend", parseBackend, "cpu or opencl", sim.backend));
    RUBBLE_TRY(overrideEnum(o.integrator, "--integrator", parseIntegrator, "symplectic or explicit",
                            sim.integrator));
    RUBBLE_TRY(overrideEnum(o.solver, "--solver", parseSolverType,
                            "pgs, jacobi, lcp-jacobi or lemke", sim.solver.type));
    if (o.collision) {
        CollisionMethod m = CollisionMethod::Sat;
        RUBBLE_TRY(overrideEnum(o.collision, "--collision", parseCollisionMethod, "sat or particles", m));
        sim.collision.method = m;
    }
    return {};
}

int report(const Error& e) {
    std::fprintf(stderr, "rubble: %s\n", e.describe().c_str());
    switch (e.kind) {
    case ErrorKind::BadInput:
    case ErrorKind::NotSupported:
        return kExitBadInput;
    case ErrorKind::Numerical:
        return kExitNumerical;
    case ErrorKind::Limit:
        return kExitLimit;
    case ErrorKind::Interrupted:
        return kExitInterrupted;
    default:
        return kExitFailure;
    }
}

} // namespace rubble::app
