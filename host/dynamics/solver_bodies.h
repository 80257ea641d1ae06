// host/dynamics/solver_bodies.h: the bodies as CPU stages 5 and 6 see them: velocities and inverse
// masses, with static and sleeping bodies given infinite mass so that no impulse moves them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "rubble/shared/body.h"

namespace rubble {

/// Four float lanes (the GCC and Clang vector extension, compiled to SSE or NEON) for the
/// solver's inner loops. A 3-vector keeps its fourth lane at zero.
using Lanes = float __attribute__((vector_size(16)));

inline Lanes toLanes(glm::vec3 v) {
    return Lanes{v.x, v.y, v.z, 0.0f};
}
inline glm::vec3 fromLanes(Lanes v) {
    return glm::vec3(v[0], v[1], v[2]);
}
/// x + y + z: a dot product once the lanes are multiplied.
inline float sum3(Lanes v) {
    return v[0] + v[1] + v[2];
}

/// A body's velocity in the solve, 32 bytes so that the rows' random reads hit one cache line.
struct SolverVelocity {
    Lanes linear{};  ///< m/s
    Lanes angular{}; ///< rad/s
};

/// J v of a row along d: the relative velocity of b against a at the contact point.
inline float rowSpeed(const SolverVelocity& a, const SolverVelocity& b, Lanes d, Lanes crossA,
                      Lanes crossB) {
    return sum3(d * (b.linear - a.linear) + crossB * b.angular - crossA * a.angular);
}

/// M^-1 J^T lambda onto both bodies' velocities.
inline void applyRow(SolverVelocity& a, SolverVelocity& b, Lanes d, Lanes turnA, Lanes turnB,
                     float inverseMassA, float inverseMassB, float lambda) {
    a.linear -= d * (inverseMassA * lambda);
    a.angular -= turnA * lambda;
    b.linear += d * (inverseMassB * lambda);
    b.angular += turnB * lambda;
}

/// One solve's view of every body, by body index. World frame throughout.
struct SolverBodies {
    std::vector<SolverVelocity> velocity;
    std::vector<SolverVelocity> push;      ///< split position pass: displacement per s
    std::vector<float> inverseMass;        ///< 1/kg; 0 when the body does not move in the solve
    std::vector<glm::mat3> inverseInertia; ///< I_w^-1, 1/(kg m^2); 0 when it does not move

    /// True when impulses change the body's velocity (dynamic and awake).
    bool moves(std::uint32_t i) const { return inverseMass[i] > 0.0f; }
};

/// True for a dynamic body that is awake.
inline bool isAwakeDynamic(const shared::BodyMass& m) {
    return m.inverseMass > 0.0f && (m.flags & RUBBLE_BODY_ASLEEP) == 0u;
}

/// Inverse masses and world inverse inertias (shared::inverseInertiaWorldItem) at the current
/// orientations. reads: masses, poses   writes: bodies.inverseMass, bodies.inverseInertia
void gatherSolverMasses(std::span<const shared::BodyMass> masses,
                        std::span<const shared::BodyPose> poses, SolverBodies& bodies);

/// reads: velocities   writes: bodies.velocity
void gatherSolverVelocities(std::span<const shared::BodyVelocity> velocities, SolverBodies& bodies);

/// Writes the solved velocities of the bodies that move back. reads: bodies   writes: velocities
void scatterSolverVelocities(const SolverBodies& bodies,
                             std::span<shared::BodyVelocity> velocities);

} // namespace rubble
