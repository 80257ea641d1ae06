// host/dynamics/contact_rows.h: CPU stage 5, buildContactRows for contacts: each manifold point
// becomes a normal row and two friction rows; last step's impulses, matched by feature id,
// warm-start them.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "host/collision/contact.h"
#include "host/core/union_find.h"
#include "host/dynamics/solver_bodies.h"
#include "rubble/scene.h"
#include "rubble/shared/body.h"
#include "rubble/shared/pgs_row.h"

namespace rubble {

/// A contact point's normal row. An impulse lambda pushes body b by +lambda n and body a by
/// -lambda n at the contact point. Vectors are world-frame Lanes (fourth lane zero).
struct NormalRow {
    Lanes normal{};           ///< unit, from a to b
    Lanes crossA{}, crossB{}; ///< r_a x n, r_b x n, m (r from each centre of mass)
    Lanes turnA{}, turnB{};   ///< I_a^-1 (r_a x n), I_b^-1 (r_b x n), 1/(kg m)
    std::uint32_t a = 0, b = 0;
    float inverseMassA = 0, inverseMassB = 0; ///< 1/kg
    float mass = 0;                           ///< 1 / (J M^-1 J^T), kg
    float targetSpeed = 0;                    ///< normal velocity the solve aims at, m/s
    float pushSpeed = 0;                      ///< Baumgarte speed of the split position pass, m/s
    float pushTarget = 0;    ///< what the split pass aims at: pushSpeed, or a bounce's lift, m/s
    float bounceSpeed = 0;   ///< normal velocity a bounce leaves with (0: none), m/s
    float bounceLift = 0;    ///< the split pass's speed that lifts a bounce off the contact, m/s
    float impulse = 0;       ///< accumulated, N s
    float pushImpulse = 0;   ///< accumulated in the position pass, N s
    float bounceImpulse = 0; ///< the restitution pass's, N s
};

/// The same point's two friction rows, along two unit tangents. The impulses sit next to the
/// tangents: the passes after the sweeps (unpackContactImpulses, storeContactImpulses) read or
/// write only these, and a large scene's rows come from memory.
struct FrictionRows {
    Lanes tangent[2] = {};
    float impulse[2] = {0, 0}; ///< accumulated, N s
    std::uint32_t a = 0, b = 0;
    Lanes crossA[2] = {}, crossB[2] = {};
    Lanes turnA[2] = {}, turnB[2] = {};
    float inverseMassA = 0, inverseMassB = 0;
    float mass[2] = {0, 0};
    float friction = 0; ///< combined Coulomb coefficient
};

/// Where a contact point came from, to hand its impulses to the next step.
struct ContactKey {
    std::uint32_t a = 0, b = 0, feature = 0;
    glm::vec3 pointInA{0.0f}; ///< the contact point in a's frame, m
};

/// What a PGS sweep reads of a point's normal row, packed into 80 bytes (solveContactSweep): the
/// fourth lanes of the five vectors carry the row's scalars, and are masked off where a vector is
/// applied to velocities; body indices sit in lanes that only applied vectors have, so that their
/// bits never enter arithmetic as (denormal) floats. The inverse masses come from the bodies
/// (SolverBodies::inverseMass, which the rows copy). A large scene's rows do not fit in the
/// caches, and every sweep streams them from memory again: fewer bytes, faster sweeps.
struct SweepNormal {
    Lanes normal{}; ///< fourth lane: mass, kg
    Lanes crossA{}; ///< fourth lane: targetSpeed, m/s
    Lanes crossB{}; ///< fourth lane: zero
    Lanes turnA{};  ///< fourth lane: body a's index (its bits)
    Lanes turnB{};  ///< fourth lane: body b's index (its bits)
};
static_assert(sizeof(SweepNormal) == 80);

/// What a PGS sweep reads and writes of a point's friction rows, packed into 160 bytes the same
/// way. The friction bound is mu times the point's normal impulse (SweepRows::normalImpulse).
struct SweepFriction {
    Lanes tangent[2] = {}; ///< fourth lanes: inverseMassA, inverseMassB, 1/kg
    Lanes crossA[2] = {};  ///< fourth lanes: mass[0], mass[1], kg
    Lanes crossB[2] = {};  ///< fourth lanes: impulse[0], impulse[1], N s
    Lanes turnA[2] = {};   ///< fourth lanes: the indices of bodies a and b (their bits)
    Lanes turnB[2] = {};   ///< fourth lanes: the friction coefficient, zero
};
static_assert(sizeof(SweepFriction) == 160);

/// The sweeps' order of a set of rows (orderSweepRows): by island (the rows joined through the
/// moving bodies they share), then within each island's blocks of rows by wave, then as in
/// ContactRows. A row's wave is one more than the latest wave among the earlier rows that share a
/// moving body with it, so that rows of one wave touch no moving body twice and each body's rows
/// keep their order. Gauss-Seidel then gives the same bits as over ContactRows' order (a row reads
/// and writes only its two bodies, and a body that does not move keeps its velocity), while
/// consecutive rows rarely wait on each other's velocities (in ContactRows' order most rows share
/// a body with the one before: pairs are sorted by body), and an island's rows can run all their
/// sweeps from the caches.
struct SweepOrder {
    std::vector<std::uint32_t> place;       ///< each ContactRows row's index here
    std::vector<std::uint32_t> order;       ///< the ContactRows row at each index here
    std::vector<std::uint32_t> islandStart; ///< where each island's rows start, then the end
    // Scratch of the ordering: islands of bodies, by body, rows by island, by wave.
    UnionFind islands;
    std::vector<std::uint32_t> byBody, byIsland, waveStart;
};

/// The rows in the PGS sweeps' packed form (packContactRows), in the sweeps' order.
struct SweepRows : SweepOrder {
    std::vector<SweepNormal> normals;
    std::vector<SweepFriction> frictions;
    std::vector<float> normalImpulse; ///< each point's accumulated normal impulse, N s
};

/// The first three lanes of a packed row's vector, the fourth (which carries a scalar) cleared:
/// ready to be applied to velocities.
inline Lanes xyz(Lanes v) {
    using Bits = std::uint32_t __attribute__((vector_size(16)));
    constexpr Bits kMask = {~0u, ~0u, ~0u, 0u};
    return Lanes((Bits)v & kMask);
}

/// A body index carried in a packed row's float lane, bit for bit, and back.
inline float indexLane(std::uint32_t i) {
    return std::bit_cast<float>(i);
}
inline std::uint32_t laneIndex(float lane) {
    return std::bit_cast<std::uint32_t>(lane);
}

/// A point's normal row in the packed form, aiming at `target` (its target speed in the velocity
/// sweeps, its push target in the position pass).
inline SweepNormal packNormal(const NormalRow& r, float target) {
    SweepNormal p;
    p.normal = r.normal;
    p.normal[3] = r.mass;
    p.crossA = r.crossA;
    p.crossA[3] = target;
    p.crossB = r.crossB;
    p.crossB[3] = 0.0f;
    p.turnA = r.turnA;
    p.turnA[3] = indexLane(r.a);
    p.turnB = r.turnB;
    p.turnB[3] = indexLane(r.b);
    return p;
}

/// A point's friction rows in the packed form, impulses included.
inline SweepFriction packFriction(const FrictionRows& f) {
    SweepFriction q;
    for (int k = 0; k < 2; ++k) {
        q.tangent[k] = f.tangent[k];
        q.crossA[k] = f.crossA[k];
        q.crossA[k][3] = f.mass[k];
        q.crossB[k] = f.crossB[k];
        q.crossB[k][3] = f.impulse[k];
        q.turnA[k] = f.turnA[k];
        q.turnB[k] = f.turnB[k];
    }
    q.tangent[0][3] = f.inverseMassA;
    q.tangent[1][3] = f.inverseMassB;
    q.turnA[0][3] = indexLane(f.a);
    q.turnA[1][3] = indexLane(f.b);
    q.turnB[0][3] = f.friction;
    q.turnB[1][3] = 0.0f;
    return q;
}

/// How many points ahead the passes over packed rows ask for their bodies' velocities, and twice
/// as far for the rows themselves (the bodies' indices are read from them): the rows stream from
/// memory, the velocities are read at random, and neither arrives in time unasked.
inline constexpr std::size_t kPrefetchRows = 8;

/// Asks for every cache line of `x`.
template <typename T> void prefetchLines(const T& x) {
    for (std::size_t at = 0; at < sizeof(T); at += 64)
        __builtin_prefetch(reinterpret_cast<const char*>(&x) + at);
}

/// This step's contact rows; the three arrays run in parallel, one entry per contact point,
/// point-major: every manifold's first point, then every second point, and so on, manifold order
/// kept within each, so that no corner of a face contact is always solved first. The sweeps run
/// in an order with the same result and fewer waits (SweepRows).
struct ContactRows {
    std::vector<NormalRow> normals;
    std::vector<FrictionRows> frictions;
    std::vector<ContactKey> keys;
    std::vector<std::uint32_t> built; ///< each row's index in manifold order
    // The split position pass: its rows, and the bodies that pushing rows move.
    std::vector<std::uint32_t> pushRows;
    std::vector<std::uint8_t> pushedBody;
    std::vector<std::uint32_t> bounceRows; ///< the restitution pass's rows
    // The layer pass: each body's layer above the bodies that do not move, its rows in order.
    std::vector<std::uint32_t> layer, layerRows;
    std::vector<std::uint8_t> loaded;
    SweepRows sweep;     ///< the PGS sweeps' packed copy, valid inside solvePgs
    SweepRows pushSweep; ///< the split position pass's packed normal rows (solvePushes)

    std::size_t size() const { return normals.size(); }
    void clear() {
        normals.clear();
        frictions.clear();
        keys.clear();
        built.clear();
    }
};

/// A contact point's impulses at the end of a step, for warm-starting the next one.
struct ContactImpulse {
    std::uint32_t a = 0, b = 0, feature = 0;
    glm::vec3 pointInA{0.0f}; ///< the contact point in a's frame, m
    float normal = 0;         ///< N s
    glm::vec3 friction{0.0f}; ///< world frame, N s (the tangents change between steps)
};

/// What the contact rows depend on besides the manifolds (SolverOptions, and the step).
struct ContactRowSettings {
    float dt = 1.0f / 60.0f; ///< s
    float baumgarte = 0.2f;  ///< fraction of the penetration beyond the slop removed per step
    float slop = 0.005f;     ///< penetration left alone, m
    bool warmStart = true;
    /// The manifolds are particle contacts, one point each and many to a pair: each takes the
    /// old impulses of its own feature alone, as the device's particlePairs does.
    bool particleContacts = false;
};

/// Approach speeds below this do not bounce (resting contacts stay at rest), m/s: the kernels'
/// value (rubble/shared/constants.h).
inline constexpr float kRestitutionThreshold = RUBBLE_RESTITUTION_THRESHOLD;

/// The Baumgarte push-out speed is at most this, m/s: a deep penetration (a fast body caught a
/// step late) is undone over a few steps instead of throwing the bodies apart.
inline constexpr float kMaxPushSpeed = RUBBLE_MAX_PUSH_SPEED;

/// A point whose feature id is new takes over the impulses of last step's unmatched point of
/// the same pair nearest to it in a's frame, if within this distance, m: clipping can renumber
/// the features of a resting box whose corners sit exactly on another's edges.
inline constexpr float kWarmStartMatchDistance = RUBBLE_WARM_START_MATCH_DISTANCE;

/// True when the (unordered) pair of bodies is in `joined`, which is sorted with a < b.
bool isJoinedPair(std::span<const BodyPair> joined, std::uint32_t a, std::uint32_t b);

/// Stage buildContactRows for contacts (Catto, "Iterative Dynamics with Temporal Coherence",
/// GDC 2005; "Modeling and Solving Constraints", GDC 2009). Each point's rows come from
/// shared::pgsContactRowItem, the function the device's buildPgsRows calls. Manifolds between two
/// bodies that do not move in the solve, or between joined bodies, are skipped. The normal row's
/// velocity target is 0, or for a gap (depth < 0) the speed that closes it within the step and
/// no further. A bounce is left to the restitution pass after the positions moved
/// (solveRestitution), from the contact: its speed is e v_contact, v_contact the approach
/// speed before this step's forces (`beforeForces`) carried over the gap by the forces'
/// acceleration, when v_contact exceeds kRestitutionThreshold (as Box2D v3 keeps the relative
/// velocity of its contact prepare, before gravity, and applies restitution last;
/// shared::bounceItem). Its Baumgarte speed min(beta/dt max(depth - slop, 0), kMaxPushSpeed) goes
/// to the split position pass (Catto, "Fast and Simple Physics using Sequential Impulses",
/// GDC 2006: split impulses), where it moves the bodies out without adding to their velocities.
/// The first tangent follows the sliding direction when there is one. Friction is
/// sqrt(mu_a mu_b), restitution max(e_a, e_b). Warm start: last step's impulses of the same
/// (pair, feature), else of the nearest unmatched point (see kWarmStartMatchDistance), the
/// friction impulse projected on the new tangents. Each row is built at its point-major place
/// (ContactRows), so the rows need no reordering afterwards.
/// reads: manifolds, poses, bodies (velocities and inverse masses), velocities before the forces,
/// materials, last impulses (sorted by pair)   writes: rows
void buildContactRows(std::span<const Manifold> manifolds, std::span<const shared::BodyPose> poses,
                      const SolverBodies& bodies,
                      std::span<const shared::BodyVelocity> beforeForces,
                      std::span<const MaterialDesc> materials,
                      std::span<const std::uint32_t> materialOf, std::span<const BodyPair> joined,
                      std::span<const ContactImpulse> last, const ContactRowSettings& settings,
                      ContactRows& rows);

/// The impulses for the next step's warm start, in pair order: the rows' accumulated impulses,
/// and those of `previous` (last step's) whose two bodies both stood still in this solve (static
/// or asleep: their contacts made no rows), so that an island woken later starts from the
/// impulses it fell asleep with instead of from nothing.
/// reads: rows, previous, bodies (which move)   writes: impulses, scratch
void storeContactImpulses(const ContactRows& rows, std::span<const ContactImpulse> previous,
                          const SolverBodies& bodies, std::vector<ContactImpulse>& impulses,
                          std::vector<ContactImpulse>& scratch);

/// Two unit tangents that make a right-handed basis with the unit normal n, the same for the
/// same n.
void tangentBasis(glm::vec3 n, glm::vec3& t1, glm::vec3& t2);

} // namespace rubble
