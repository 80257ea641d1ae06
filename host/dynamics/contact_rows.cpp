// host/dynamics/contact_rows.cpp: CPU stage 5 for contacts: normal and friction rows per
// manifold point, warm-started from last step's impulses.
#include "host/dynamics/contact_rows.h"

#include <algorithm>
#include <cmath>

#include "host/core/assert.h"
#include "host/core/math.h"
#include "rubble/shared/pgs_row.h"

namespace rubble {
namespace {

// The arms of side `side` (0: a, 1: b) of a contact's rows for a body of infinite mass that
// turns: the shared rows leave them zero for a body that does not move (static, asleep), whose
// angular velocity is zero; a kinematic body's is not. Rows of bodies that do not turn are left
// as they are, bit for bit.
void turningWall(NormalRow& nr, FrictionRows& fr, int side, const SolverVelocity& v, glm::vec3 arm,
                 float inverseMass) {
    if (inverseMass > 0.0f || (v.angular[0] == 0.0f && v.angular[1] == 0.0f && v.angular[2] == 0.0f))
        return;
    Lanes& normal = side == 0 ? nr.crossA : nr.crossB;
    normal = toLanes(glm::cross(arm, fromLanes(nr.normal)));
    for (int d = 0; d < 2; ++d)
        (side == 0 ? fr.crossA[d] : fr.crossB[d]) = toLanes(glm::cross(arm, fromLanes(fr.tangent[d])));
}

// Last step's impulses are sorted by pair (storeContactImpulses).
bool pairLess(const ContactImpulse& x, const ContactImpulse& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
}

bool keyLess(const ContactImpulse& x, std::uint32_t a, std::uint32_t b, std::uint32_t feature) {
    if (x.a != a) return x.a < a;
    if (x.b != b) return x.b < b;
    return x.feature < feature;
}

shared::float4 toFloat4(Lanes v) {
    return shared::float4{v[0], v[1], v[2], v[3]};
}
Lanes toLanes(shared::float4 v) {
    return Lanes{v.x, v.y, v.z, v.w};
}
shared::BodyVelocity sharedVelocity(const SolverVelocity& v) {
    return shared::BodyVelocity{toFloat4(v.linear), toFloat4(v.angular)};
}

// Where findRun found the last pair's run in `last`.
struct RunCursor {
    std::uint32_t a = 0, b = 0;
    std::size_t at = 0;
};

// The first of last step's impulses of pair (a, b) or after it: std::lower_bound over all of
// `last`, which is sorted by pair. The manifolds come in pair order, so the search gallops on
// from the previous pair's run (every entry before it is below that pair, hence below this one)
// instead of bisecting all of `last` again for each manifold.
std::size_t findRun(std::span<const ContactImpulse> last, std::uint32_t a, std::uint32_t b,
                    RunCursor& cursor) {
    auto below = [&](const ContactImpulse& x) { return keyLess(x, a, b, 0u); };
    const bool onward = a != cursor.a ? a > cursor.a : b >= cursor.b;
    std::size_t low = onward ? cursor.at : 0, high = last.size();
    if (onward) {
        // Doubling steps until an entry not below the pair bounds the run's start.
        high = low;
        for (std::size_t step = 1; high < last.size() && below(last[high]); step *= 2) {
            low = high + 1;
            high = low + step;
        }
        high = std::min(high, last.size());
    }
    const auto from = last.begin() + std::ptrdiff_t(low);
    const auto run = std::partition_point(from, last.begin() + std::ptrdiff_t(high), below);
    cursor = RunCursor{a, b, std::size_t(run - last.begin())};
    return cursor.at;
}

// Row `row` starts from an old point's impulses, its friction in its own tangents.
void takeImpulse(ContactRows& rows, std::size_t row, const ContactImpulse& from) {
    rows.normals[row].impulse = from.normal;
    FrictionRows& f = rows.frictions[row];
    f.impulse[0] = glm::dot(from.friction, fromLanes(f.tangent[0]));
    f.impulse[1] = glm::dot(from.friction, fromLanes(f.tangent[1]));
}

// Hands last step's impulses to one manifold's new points (point k's rows at at[k]): the same
// feature first, then the nearest unmatched old point within kWarmStartMatchDistance. `last`
// starts at the pair's run.
void warmStart(ContactRows& rows, const std::size_t* at, std::size_t count,
               std::span<const ContactImpulse> last) {
    const ContactKey& key = rows.keys[at[0]];
    // A manifold has at most 4 points; more old points than 8 would be a different narrow phase.
    constexpr std::size_t kMaxOld = 8;
    std::size_t old = 0;
    while (old < last.size() && old < kMaxOld && last[old].a == key.a && last[old].b == key.b)
        ++old;
    if (old == 0) return;
    bool taken[kMaxOld] = {};
    bool matched[4] = {};
    for (std::size_t k = 0; k < count; ++k)
        for (std::size_t o = 0; o < old; ++o)
            if (!taken[o] && last[o].feature == rows.keys[at[k]].feature) {
                takeImpulse(rows, at[k], last[o]);
                taken[o] = matched[k] = true;
                break;
            }
    for (std::size_t k = 0; k < count; ++k) {
        if (matched[k]) continue;
        float best = kWarmStartMatchDistance * kWarmStartMatchDistance;
        std::size_t pick = old;
        for (std::size_t o = 0; o < old; ++o) {
            if (taken[o]) continue;
            const glm::vec3 d = last[o].pointInA - rows.keys[at[k]].pointInA;
            if (glm::dot(d, d) < best) {
                best = glm::dot(d, d);
                pick = o;
            }
        }
        if (pick == old) continue;
        takeImpulse(rows, at[k], last[pick]);
        taken[pick] = true;
    }
}

// Particle contacts (one-point manifolds, many to a pair): the old point of the same feature
// anywhere in the pair's run, as the device's particlePairs finds the same key; a new contact
// starts from nothing (no nearest point: its neighbours have impulses of their own). The run's
// points are in the order of this step's (by particle), so the search starts after the last
// match (`cursor`, an index into `run`) and wraps once.
void warmStartParticle(ContactRows& rows, std::size_t row, std::span<const ContactImpulse> run,
                       std::size_t& cursor) {
    const std::uint32_t feature = rows.keys[row].feature;
    for (std::size_t i = 0; i < run.size(); ++i) {
        const std::size_t o = (cursor + i) % run.size();
        if (run[o].feature != feature) continue;
        takeImpulse(rows, row, run[o]);
        cursor = o + 1;
        return;
    }
}

} // namespace

bool isJoinedPair(std::span<const BodyPair> joined, std::uint32_t a, std::uint32_t b) {
    if (joined.empty()) return false;
    const BodyPair key{std::min(a, b), std::max(a, b)};
    return std::binary_search(joined.begin(), joined.end(), key);
}

void tangentBasis(glm::vec3 n, glm::vec3& t1, glm::vec3& t2) {
    // Cross with the axis least aligned with n (Catto, "Computing a basis", 2014).
    t1 = toVec3(shared::perpendicularItem(toFloat4(n)));
    t2 = glm::cross(n, t1);
}

void buildContactRows(std::span<const Manifold> manifolds, std::span<const shared::BodyPose> poses,
                      const SolverBodies& bodies,
                      std::span<const shared::BodyVelocity> beforeForces,
                      std::span<const MaterialDesc> materials,
                      std::span<const std::uint32_t> materialOf, std::span<const BodyPair> joined,
                      std::span<const ContactImpulse> last, const ContactRowSettings& settings,
                      ContactRows& rows) {
    const float dt = settings.dt;
    auto makesRows = [&](const Manifold& m) {
        return m.count > 0 && (bodies.moves(m.a) || bodies.moves(m.b)) &&
               !isJoinedPair(joined, m.a, m.b);
    };
    // Each row is built at its place in point-major order (every manifold's first point, then
    // every second point, and so on, manifold order kept within each): start[k] is where the
    // next manifold's point k goes.
    std::size_t start[5] = {0, 0, 0, 0, 0};
    for (const Manifold& m : manifolds) {
        if (!makesRows(m)) continue;
        RUBBLE_ASSERT(m.count <= m.points.size());
        for (std::uint32_t k = 0; k < m.count; ++k) ++start[k + 1];
    }
    for (int k = 0; k < 4; ++k) start[k + 1] += start[k];
    // Every row below is written whole, so the arrays keep last step's entries instead of being
    // cleared and filled with zeros first (a pass over some 350 bytes a point).
    rows.normals.resize(start[4]);
    rows.frictions.resize(start[4]);
    rows.keys.resize(start[4]);
    rows.built.resize(start[4]);
    std::uint32_t inManifoldOrder = 0;
    // Particle contacts: the old run of the pair the last manifold was in, and where in it the
    // next contact's search starts.
    std::span<const ContactImpulse> particleRun;
    std::size_t particleCursor = 0;
    // The previous manifold's pair and where its old run starts (findRun).
    RunCursor lastRun;
    for (const Manifold& m : manifolds) {
        if (!makesRows(m)) continue;
        const MaterialDesc& matA = materials[materialOf[m.a]];
        const MaterialDesc& matB = materials[materialOf[m.b]];
        const float friction = std::sqrt(matA.friction * matB.friction);
        const float restitution = std::max(matA.restitution, matB.restitution);
        const glm::vec3 xa = toVec3(poses[m.a].position);
        const SolverVelocity& bodyA = bodies.velocity[m.a];
        const SolverVelocity& bodyB = bodies.velocity[m.b];
        const float ima = bodies.inverseMass[m.a], imb = bodies.inverseMass[m.b];
        const glm::mat3& ia = bodies.inverseInertia[m.a];
        const glm::mat3& ib = bodies.inverseInertia[m.b];
        const glm::vec3 n = m.normal;

        const shared::float4 normal = toFloat4(n);
        const shared::float4 positionA = poses[m.a].position, positionB = poses[m.b].position;
        const shared::BodyVelocity velocityA = sharedVelocity(bodyA),
                                   velocityB = sharedVelocity(bodyB);
        const shared::Mat3 inertiaA = toShared(ia), inertiaB = toShared(ib);
        const shared::float4 fixedTangent = shared::perpendicularItem(normal);

        std::size_t at[4] = {0, 0, 0, 0};
        for (std::uint32_t k = 0; k < m.count; ++k) {
            at[k] = start[k]++;
            rows.built[at[k]] = inManifoldOrder++;
            const ContactPoint& p = m.points[k];
            const glm::vec3 ra = p.position - xa;
            // The rows themselves come from the code the device runs (rubble/shared/pgs_row.h).
            const shared::PgsContactRow row = shared::pgsContactRowItem(
                toFloat4(p.position), p.depth, normal, positionA, positionB, velocityA, velocityB,
                beforeForces[m.a], beforeForces[m.b], ima, imb, inertiaA, inertiaB, friction,
                restitution, settings.baumgarte, settings.slop, dt, fixedTangent);

            const shared::PgsNormalRow& rn = row.normal;
            NormalRow nr;
            nr.a = m.a;
            nr.b = m.b;
            nr.normal = toLanes(rn.normal);
            nr.crossA = toLanes(rn.crossA);
            nr.crossB = toLanes(rn.crossB);
            nr.turnA = toLanes(rn.turnA);
            nr.turnB = toLanes(rn.turnB);
            nr.inverseMassA = ima;
            nr.inverseMassB = imb;
            nr.mass = rn.mass.x;
            nr.targetSpeed = rn.speeds.x;
            nr.pushSpeed = rn.speeds.y;
            nr.bounceSpeed = rn.mass.y;
            nr.bounceLift = rn.mass.z;

            const shared::PgsFrictionRows& rf = row.friction;
            FrictionRows fr;
            fr.a = m.a;
            fr.b = m.b;
            fr.inverseMassA = ima;
            fr.inverseMassB = imb;
            fr.friction = friction;
            for (int d = 0; d < 2; ++d) {
                fr.tangent[d] = toLanes(rf.tangent[d]);
                fr.crossA[d] = toLanes(rf.crossA[d]);
                fr.crossB[d] = toLanes(rf.crossB[d]);
                fr.turnA[d] = toLanes(rf.turnA[d]);
                fr.turnB[d] = toLanes(rf.turnB[d]);
                fr.mass[d] = d == 0 ? rf.mass.x : rf.mass.y;
            }
            // A body that does not move but turns (a kinematic one) carries the contact point
            // round with it: its arm enters J v, while no impulse turns it (its turn stays 0).
            turningWall(nr, fr, 0, bodyA, ra, ima);
            turningWall(nr, fr, 1, bodyB, p.position - toVec3(positionB), imb);
            rows.normals[at[k]] = nr;
            rows.frictions[at[k]] = fr;

            ContactKey& key = rows.keys[at[k]];
            key.a = m.a;
            key.b = m.b;
            key.feature = p.feature;
            key.pointInA = toVec3(shared::quatRotateInverse(poses[m.a].orientation, toFloat4(ra)));
        }
        if (settings.warmStart && settings.particleContacts) {
            // Last step's impulses of this pair: a run, found once for the pair's contacts.
            if (particleRun.empty() || particleRun.front().a != m.a ||
                particleRun.front().b != m.b) {
                const auto [from, to] =
                    std::equal_range(last.begin(), last.end(), ContactImpulse{m.a, m.b}, pairLess);
                particleRun =
                    last.subspan(std::size_t(from - last.begin()), std::size_t(to - from));
                particleCursor = 0;
            }
            for (std::uint32_t k = 0; k < m.count && !particleRun.empty(); ++k)
                warmStartParticle(rows, at[k], particleRun, particleCursor);
        } else if (settings.warmStart) {
            // Last step's impulses of this pair: a sorted run.
            const std::size_t run = findRun(last, m.a, m.b, lastRun);
            warmStart(rows, at, m.count, last.subspan(run));
        }
    }
}

void storeContactImpulses(const ContactRows& rows, std::span<const ContactImpulse> previous,
                          const SolverBodies& bodies, std::vector<ContactImpulse>& impulses,
                          std::vector<ContactImpulse>& scratch) {
    scratch.resize(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const ContactKey& key = rows.keys[i];
        const FrictionRows& f = rows.frictions[i];
        ContactImpulse& c = scratch[rows.built.empty() ? i : rows.built[i]];
        c.a = key.a;
        c.b = key.b;
        c.feature = key.feature;
        c.pointInA = key.pointInA;
        c.normal = rows.normals[i].impulse;
        c.friction = fromLanes(f.tangent[0] * f.impulse[0] + f.tangent[1] * f.impulse[1]);
    }
    // The narrow phase hands the manifolds over in pair order; anything else is sorted here.
    if (!std::is_sorted(scratch.begin(), scratch.end(), pairLess))
        std::stable_sort(scratch.begin(), scratch.end(), pairLess);
    // Merge in the still pairs' impulses; a pair with rows has a moving body, so none repeats.
    // Without any, the rows' impulses are the list as they are.
    if (std::all_of(previous.begin(), previous.end(), [&](const ContactImpulse& old) {
            return bodies.moves(old.a) || bodies.moves(old.b);
        })) {
        impulses.swap(scratch);
        return;
    }
    impulses.clear();
    std::size_t next = 0;
    for (const ContactImpulse& old : previous) {
        if (bodies.moves(old.a) || bodies.moves(old.b)) continue;
        while (next < scratch.size() && pairLess(scratch[next], old))
            impulses.push_back(scratch[next++]);
        impulses.push_back(old);
    }
    impulses.insert(impulses.end(), scratch.begin() + std::ptrdiff_t(next), scratch.end());
}

} // namespace rubble
