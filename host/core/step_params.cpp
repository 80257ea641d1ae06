// host/core/step_params.cpp: the per-step parameters and the solver settings derived from the
// options and materials.
#include "host/core/step_params.h"

#include "host/core/assert.h"
#include "host/core/math.h"

namespace rubble {

using namespace shared;

StepParams makeStepParams(const SimulationOptions& o, std::int64_t stepsTaken) {
    StepParams p;
    p.step = stepsTaken;
    p.time = double(stepsTaken) * double(o.dt);
    p.dt = o.dt;
    p.gravity = toFloat4(o.gravity);
    p.integrator = o.integrator;
    p.collision = o.collisionMethod();
    p.particleSpacing = o.collision.particleSpacing;
    p.continuous = o.continuous;
    p.recycleContacts = o.collision.recycleContacts;
    p.solver = o.solver;
    p.rows = solverParams(o);
    p.jacobiRelaxation = jacobiRelaxation(o.solver);
    p.lcpJacobiRelaxation = lcpJacobiRelaxation(o.solver);
    p.sleep = o.sleep;
    return p;
}

float jacobiRelaxation(const SolverOptions& o) {
    return o.relaxation * kJacobiOverRelaxation;
}

float lcpJacobiRelaxation(const SolverOptions& o) {
    return o.relaxation * kLcpJacobiOverRelaxation;
}

SolverParams solverParams(const SimulationOptions& o) {
    const SolverOptions& s = o.solver;
    const bool particles = o.collisionMethod() == CollisionMethod::Particles;
    const float slop = particles ? particleSlopItem(s.slop, o.collision.particleSpacing) : s.slop;
    return SolverParams{s.baumgarte, slop, 1.0f / o.dt, s.relaxation};
}

std::vector<float4> bodySurfaces(std::span<const MaterialDesc> materials,
                                 std::span<const std::uint32_t> materialOf) {
    std::vector<float4> out(materialOf.size());
    for (std::size_t b = 0; b < materialOf.size(); ++b) {
        const MaterialDesc& m = materials[materialOf[b]];
        out[b] = vec4(m.friction, m.restitution, 0.0f);
    }
    return out;
}

std::uint32_t lcpStride(std::span<const float4> surfaces, std::span<const BodyMass> masses) {
    RUBBLE_ASSERT(surfaces.size() == masses.size());
    std::size_t rough = 0;
    bool dynamicRough = false;
    for (std::size_t b = 0; b < surfaces.size(); ++b) {
        if (surfaces[b].x <= 0.0f) continue;
        ++rough;
        dynamicRough = dynamicRough || masses[b].inverseMass != 0.0f;
    }
    return rough >= 2 && dynamicRough ? 3u : 1u;
}

} // namespace rubble
