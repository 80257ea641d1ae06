// host/dynamics/contact_rows.h: CPU stage 5, buildContactRows for contacts: each manifold point
// becomes a normal row and two friction rows; last step's impulses, matched by feature id,
// warm-start them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "host/collision/contact.h"
#include "host/dynamics/solver_bodies.h"
#include "rubble/scene.h"
#include "rubble/shared/body.h"

namespace rubble {

/// One contact point's three rows: row 0 along the normal, rows 1 and 2 along two tangents. An
/// impulse lambda on row k pushes body b by +lambda direction[k] and body a by the opposite,
/// at the contact point.
struct ContactRow {
    std::uint32_t a = 0, b = 0;
    std::uint32_t feature = 0;
    glm::vec3 direction[3];         ///< unit, world: normal (a to b), tangent, tangent
    glm::vec3 crossA[3], crossB[3]; ///< r_a x d and r_b x d, m (r from each centre of mass)
    glm::vec3 turnA[3], turnB[3];   ///< I_a^-1 (r_a x d) and I_b^-1 (r_b x d), 1/(kg m)
    float mass[3];                  ///< 1 / (J M^-1 J^T) of each row, kg
    float inverseMassA = 0, inverseMassB = 0; ///< 1/kg
    float targetSpeed = 0;          ///< normal velocity the solve aims at, m/s (bias)
    float friction = 0;             ///< combined Coulomb coefficient
    float impulse[3];               ///< accumulated impulses, N s
};

/// A contact point's impulses at the end of a step, for warm-starting the next one.
struct ContactImpulse {
    std::uint32_t a = 0, b = 0, feature = 0;
    float normal = 0;             ///< N s
    glm::vec3 friction{0.0f};     ///< world frame, N s (the tangents change between steps)
};

/// What the contact rows depend on besides the manifolds (SolverOptions, and the step).
struct ContactRowSettings {
    float dt = 1.0f / 60.0f;   ///< s
    float baumgarte = 0.2f;    ///< fraction of the penetration beyond the slop removed per step
    float slop = 0.005f;       ///< penetration left alone, m
    bool warmStart = true;
};

/// Approach speeds below this do not bounce (resting contacts stay at rest), m/s.
inline constexpr float kRestitutionThreshold = 0.5f;

/// True when the (unordered) pair of bodies is in `joined`, which is sorted with a < b.
bool isJoinedPair(std::span<const BodyPair> joined, std::uint32_t a, std::uint32_t b);

/// Stage buildContactRows for contacts (Catto, "Iterative Dynamics with Temporal Coherence",
/// GDC 2005; "Modeling and Solving Constraints", GDC 2009). Manifolds between two bodies that do
/// not move in the solve, or between joined bodies, are skipped. The normal row aims at the
/// larger of the Baumgarte speed beta/dt max(depth - slop, 0) and the restitution speed
/// e v_approach (when v_approach exceeds kRestitutionThreshold); a gap (depth < 0) may close
/// within the step and no further. The first tangent follows the sliding direction when there is
/// one. Friction is sqrt(mu_a mu_b), restitution max(e_a, e_b).
/// reads: manifolds, poses, bodies (velocities and inverse masses), materials, last impulses
/// (sorted by a, b, feature)   writes: rows
void buildContactRows(std::span<const Manifold> manifolds, std::span<const shared::BodyPose> poses,
                      const SolverBodies& bodies, std::span<const MaterialDesc> materials,
                      std::span<const std::uint32_t> materialOf,
                      std::span<const BodyPair> joined, std::span<const ContactImpulse> last,
                      const ContactRowSettings& settings, std::vector<ContactRow>& rows);

/// The rows' accumulated impulses, sorted by (a, b, feature), for the next step.
/// reads: rows   writes: impulses
void storeContactImpulses(std::span<const ContactRow> rows, std::vector<ContactImpulse>& impulses);

/// Two unit tangents that make a right-handed basis with the unit normal n, the same for the
/// same n.
void tangentBasis(glm::vec3 n, glm::vec3& t1, glm::vec3& t2);

} // namespace rubble
