// host/dynamics/pgs.cpp: CPU stage 6, projected Gauss-Seidel on the bodies' velocities.
#include "host/dynamics/pgs.h"

#include <algorithm>
#include <cmath>

namespace rubble {
namespace {

// J v of row k: the relative velocity of b against a at the contact point, along direction k.
inline float rowSpeed(const ContactRow& r, int k, const SolverBodies& bodies) {
    return glm::dot(r.direction[k], bodies.linear[r.b] - bodies.linear[r.a]) +
           glm::dot(r.crossB[k], bodies.angular[r.b]) - glm::dot(r.crossA[k], bodies.angular[r.a]);
}

// M^-1 J^T lambda for row k.
inline void applyRow(const ContactRow& r, int k, float lambda, SolverBodies& bodies) {
    bodies.linear[r.a] -= r.direction[k] * (r.inverseMassA * lambda);
    bodies.angular[r.a] -= r.turnA[k] * lambda;
    bodies.linear[r.b] += r.direction[k] * (r.inverseMassB * lambda);
    bodies.angular[r.b] += r.turnB[k] * lambda;
}

} // namespace

void warmStartContacts(std::span<const ContactRow> contacts, SolverBodies& bodies) {
    for (const ContactRow& r : contacts)
        for (int k = 0; k < 3; ++k)
            if (r.impulse[k] != 0.0f) applyRow(r, k, r.impulse[k], bodies);
}

float solveContactSweep(std::span<ContactRow> contacts, SolverBodies& bodies, float relaxation) {
    float residual = 0.0f;
    for (ContactRow& r : contacts) {
        // Friction: each tangent row within the box |lambda_t| <= mu lambda_n.
        const float bound = r.friction * r.impulse[0];
        for (int k = 1; k < 3; ++k) {
            const float change = -r.mass[k] * rowSpeed(r, k, bodies) * relaxation;
            const float total = std::clamp(r.impulse[k] + change, -bound, bound);
            const float applied = total - r.impulse[k];
            r.impulse[k] = total;
            applyRow(r, k, applied, bodies);
            residual = std::max(residual, std::abs(applied));
        }
        // Normal: the accumulated impulse only pushes.
        const float change = r.mass[0] * (r.targetSpeed - rowSpeed(r, 0, bodies)) * relaxation;
        const float total = std::max(r.impulse[0] + change, 0.0f);
        const float applied = total - r.impulse[0];
        r.impulse[0] = total;
        applyRow(r, 0, applied, bodies);
        residual = std::max(residual, std::abs(applied));
    }
    return residual;
}

void solvePgs(std::span<ContactRow> contacts, std::span<Joint> joints, SolverBodies& bodies,
              const SolverOptions& options, std::vector<float>& residuals) {
    if (options.warmStart) {
        warmStartJoints(joints, bodies);
        warmStartContacts(contacts, bodies);
    }
    residuals.assign(std::size_t(std::max(options.iterations, 0)), 0.0f);
    for (float& residual : residuals) {
        for (Joint& j : joints)
            residual = std::max(residual, solveJointVelocity(j, bodies, options.relaxation));
        residual = std::max(residual, solveContactSweep(contacts, bodies, options.relaxation));
    }
}

} // namespace rubble
