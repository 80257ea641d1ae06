// host/dynamics/soft_step.h: CPU stage 6 of the soft-step solver, solveSoftStep: substeps that
// integrate the bodies, with soft contacts and joints, relax passes and restitution (Catto,
// "Solver2D", 2024; the Box2D v3 solver). The device version is host/gpu/soft_step.h.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "host/dynamics/contact_rows.h"
#include "host/dynamics/joints.h"
#include "host/dynamics/solver_bodies.h"
#include "rubble/options.h"
#include "rubble/shared/body.h"

namespace rubble {

/// A soft constraint's coefficients for one substep h (Catto, "Solver2D: soft step", and Box2D
/// v3's b2MakeSoft): with zeta the damping ratio and omega = 2 pi hertz, a1 = 2 zeta + h omega,
/// a2 = h omega a1, a3 = 1 / (1 + a2); the velocity bias is biasRate C, the impulse
/// -massScale m_eff (Cdot + biasRate C) - impulseScale lambda_accumulated.
struct Softness {
    float biasRate = 0.0f;     ///< omega / a1, 1/s
    float massScale = 1.0f;    ///< a2 a3
    float impulseScale = 0.0f; ///< a3
};

/// The coefficients of a spring of `hertz` (Hz) and `dampingRatio` over a substep of h seconds;
/// a rigid constraint without bias ({0, 1, 0}) when hertz is 0.
Softness makeSoftness(float hertz, float dampingRatio, float h);

/// What a soft contact point needs beyond its rows (ContactRows, in the same order).
struct SoftContactPoint {
    Lanes offsetA{},
        offsetB{}; ///< contact point from each centre of mass at the step's start, world, m
    glm::vec3 anchorA{0.0f}, anchorB{0.0f}; ///< the same offsets in the bodies' frames, m
    float separation = 0.0f;       ///< along the normal at the step's start, m (negative: overlap)
    float relativeVelocity = 0.0f; ///< normal speed of b against a before the step's forces, m/s
    float restitution = 0.0f;      ///< max(e_a, e_b)
    float maxNormalImpulse = 0.0f; ///< largest normal impulse of the substeps, N s
    Softness soft;                 ///< this point's spring (softnessFor)
};

/// A manifold's points: their rows' indices (ContactRows order), in the manifold's order.
struct SoftManifold {
    std::array<std::uint32_t, 4> rows{};
    std::uint32_t count = 0;
};

/// The soft step's settings of one step, from SolverOptions and dt.
struct SoftStepSettings {
    int substeps = 4;
    int relaxIterations = 1;
    float h = 1.0f / 240.0f;    ///< substep, s
    float contactHertz = 30.0f; ///< capped at a quarter of the substep rate, Hz
    float dampingRatio = 10.0f;
    float jointHertz = 60.0f; ///< Hz
    float jointDampingRatio = 2.0f;
    float maxPushSpeed = 3.0f;         ///< m/s
    float restitutionThreshold = 0.5f; ///< slower approaches do not bounce, m/s
    bool warmStart = true;
};

/// The settings for a step of dt seconds. The contact hertz is capped at a quarter of the
/// substep rate (Box2D v3's rule: stiffer than that, a substep cannot follow the spring).
SoftStepSettings makeSoftStepSettings(const SolverOptions& options, float dt);

/// The spring of a constraint between bodies of inverse masses ima and imb (0: does not move)
/// at `hertz`: against a body that does not move, `againstStill` times the hertz (contacts 2, as
/// Box2D v3's static softness: nothing on the other side gives way; joints 1). The stiffness
/// m_eff omega^2 follows the constraint's effective mass, about the lighter body's: a load of
/// weight W on it overlaps by W / (m_eff omega^2) at rest (docs/solvers.md, "Mass ratios").
Softness softnessFor(float hertz, float dampingRatio, float h, float ima, float imb,
                     float againstStill);

/// What a pass over the contact points reads of a point's normal row and spring, packed into 80
/// bytes as PGS packs its rows (SweepNormal): the fourth lanes of the vectors carry the scalars,
/// and the body indices sit in lanes that only applied vectors have. The inverse masses come
/// from the bodies (SolverBodies::inverseMass, which the rows copy).
struct SoftNormal {
    Lanes normal{}; ///< fourth lane: mass, kg
    Lanes crossA{}; ///< fourth lane: the spring's biasRate, 1/s
    Lanes crossB{}; ///< fourth lane: the spring's massScale
    Lanes turnA{};  ///< fourth lane: body a's index (its bits)
    Lanes turnB{};  ///< fourth lane: body b's index (its bits)
};
static_assert(sizeof(SoftNormal) == 80);

/// What a point's separation at the current poses needs, 80 bytes: the normal, the point's
/// offsets from the centres of mass at the step's start and in the bodies' frames.
struct SoftAnchors {
    Lanes normal{};  ///< fourth lane: the separation at the step's start, m
    Lanes offsetA{}; ///< world, m
    Lanes offsetB{};
    Lanes anchorA{}; ///< body a's frame, m; fourth lane: body a's index (its bits)
    Lanes anchorB{}; ///< body b's frame, m; fourth lane: body b's index (its bits)
};
static_assert(sizeof(SoftAnchors) == 80);

/// What a pass reads and writes of a point besides its packed rows.
struct SoftPointState {
    float separation = 0.0f;       ///< at the bodies' poses since they last moved, m
    float impulseScale = 0.0f;     ///< the spring's
    float impulse = 0.0f;          ///< accumulated normal impulse, N s
    float maxNormalImpulse = 0.0f; ///< largest normal impulse of the substeps, N s
};
static_assert(sizeof(SoftPointState) == 16);

/// The contact points in the passes' packed form, filled once per step in the sweeps' order
/// (SweepOrder: the same bits as ContactRows' order, fewer waits): a large scene's rows and
/// points do not fit in the caches, and every pass streams them from memory again (352 bytes of
/// rows and 96 of point a point, against 256 packed, and the anchors' 80 in the first pass after
/// the bodies moved). The friction rows take PGS's packed form (SweepFriction, the friction
/// impulses in it).
struct SoftPassRows {
    SweepOrder order; ///< where each ContactRows row is packed (place), and the rows by place
    std::vector<SoftNormal> normals;
    std::vector<SweepFriction> frictions;
    std::vector<SoftAnchors> anchors;
    std::vector<SoftPointState> state;
    std::vector<std::uint32_t> landings; ///< the landing manifolds (pointManifolds' indices)
    // Without joints each island (SweepOrder::islandStart) runs its substeps on its own: its
    // moving bodies and its landings, by island, and the bodies of no island.
    std::vector<std::uint32_t> islandBodies, islandBodyStart, islandLandings, islandLandingStart;
    std::vector<std::uint32_t> otherBodies;
    std::vector<std::uint8_t> grouped; ///< scratch: by body, whether an island has it
};

/// The bodies' poses during the substeps, by body index: where each body is now and how far it
/// has moved since the step began.
struct SoftPoses {
    std::vector<shared::BodyPose> pose;
    std::vector<Lanes> moved; ///< x - x_start, m
};

/// The extra data of the soft contact points: offsets, separations and approach speeds, from the
/// rows buildContactRows made from these manifolds (rows.built maps each row to its point in
/// manifold order; manifolds skipped by buildContactRows are skipped alike), and each
/// manifold's rows (pointManifolds, manifold order).
/// reads: manifolds, rows, poses, approach velocities, materials   writes: points
void prepareSoftContacts(std::span<const Manifold> manifolds, const ContactRows& rows,
                         std::span<const shared::BodyPose> poses, const SolverBodies& bodies,
                         std::span<const shared::BodyVelocity> approach,
                         std::span<const MaterialDesc> materials,
                         std::span<const std::uint32_t> materialOf,
                         std::span<const BodyPair> joined, std::vector<SoftContactPoint>& points,
                         std::vector<SoftManifold>& pointManifolds);

/// Stage solveSoftStep. The bodies' velocities start from `start` (before the step's forces);
/// each of the substeps adds 1/substeps of the forces' velocity change (`afterForces - start`),
/// warm-starts the joints and contacts with their accumulated impulses, solves the normal rows
/// of each landing manifold together (pointManifolds; a speculative point approaching faster
/// than the restitution threshold), then the joints, then the contacts once with bias (soft
/// constraints; a contact's separation is updated from the bodies' motion within the step, so
/// no new collision is needed), moves the bodies by h, and runs the relax passes (the same
/// without bias, rigid). Then restitution (rows that bounced: target speed -e v_before, as
/// Box2D v3's b2ApplyRestitution). The accumulated impulses are per substep.
/// residuals[k] is the largest |impulse change| of the k-th pass (biased or relax).
/// reads: rows, points, pointManifolds, joints, start and afterForces velocities
/// writes: bodies' velocities, poses (the poses at the step's end), impulses, packed, residuals
/// The passes run on a packed copy of the rows and points (`packed`, filled here), and each
/// point's separation is found in the first pass after the poses moved (and in the first pass)
/// and kept for the passes until they move again.
void solveSoftStep(ContactRows& rows, std::span<SoftContactPoint> points,
                   std::span<const SoftManifold> pointManifolds, std::span<Joint> joints,
                   SolverBodies& bodies, std::span<const shared::BodyVelocity> start,
                   std::span<const shared::BodyVelocity> afterForces,
                   const SoftStepSettings& settings, SoftPoses& poses, SoftPassRows& packed,
                   std::vector<float>& residuals);

} // namespace rubble
