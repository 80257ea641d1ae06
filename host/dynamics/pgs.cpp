// host/dynamics/pgs.cpp: CPU stage 6, projected Gauss-Seidel on the bodies' velocities.
#include "host/dynamics/pgs.h"

#include <algorithm>
#include <cmath>

#include "host/core/math.h"

namespace rubble {
namespace {

// A row bounces when it has a bounce speed and stopped its bodies in this step's solve: they
// reached the contact.
bool isBouncing(const NormalRow& r) {
    return r.bounceSpeed > 0.0f && r.impulse > 0.0f;
}

// The position pass stops when no push impulse changes by more than this, N s.
constexpr float kPushTolerance = 1e-6f;

constexpr std::uint32_t kNoLayer = 0xffffffffu;
// What solveLayers marks on a body: it carries a heavy load, or it is in a joint.
constexpr std::uint8_t kLoaded = 1, kJoined = 2;

// Each body's layer: 0 for a body that does not move, else one more than the lowest layer it
// touches through a row (kNoLayer when nothing links it to a body that does not move).
void findLayers(const ContactRows& contacts, const SolverBodies& bodies,
                std::vector<std::uint32_t>& layer) {
    const std::size_t n = bodies.velocity.size();
    layer.assign(n, kNoLayer);
    for (std::size_t i = 0; i < n; ++i)
        if (!bodies.moves(std::uint32_t(i))) layer[i] = 0;
    for (bool changed = true; changed;) {
        changed = false;
        for (const NormalRow& r : contacts.normals) {
            if (layer[r.a] != kNoLayer && layer[r.a] + 1 < layer[r.b]) {
                layer[r.b] = layer[r.a] + 1;
                changed = true;
            }
            if (layer[r.b] != kNoLayer && layer[r.b] + 1 < layer[r.a]) {
                layer[r.a] = layer[r.b] + 1;
                changed = true;
            }
        }
    }
}

// One update of a normal row that moves only the body on `upper`'s side (the other one held, as
// if it did not move), from the accumulated impulse `total`, clamped >= 0.
void solveNormalRowOnto(const NormalRow& r, SolverVelocity& a, SolverVelocity& b, bool upperIsB,
                        float target, float& total) {
    const float speed = rowSpeed(a, b, r.normal, r.crossA, r.crossB);
    const float k = upperIsB ? r.inverseMassB + sum3(r.crossB * r.turnB)
                             : r.inverseMassA + sum3(r.crossA * r.turnA);
    if (k <= 0.0f) return;
    const float next = std::max(total + (target - speed) / k, 0.0f);
    const float applied = next - total;
    total = next;
    if (upperIsB) {
        b.linear += r.normal * (r.inverseMassB * applied);
        b.angular += r.turnB * applied;
    } else {
        a.linear -= r.normal * (r.inverseMassA * applied);
        a.angular -= r.turnA * applied;
    }
}

} // namespace

void solveLayers(ContactRows& contacts, std::span<const Joint> joints, SolverBodies& bodies) {
    std::vector<std::uint32_t>& rows = contacts.layerRows;
    rows.clear();
    // Bodies in joints keep out: the pass would move one without its partner.
    std::vector<std::uint8_t>& loaded = contacts.loaded;
    loaded.assign(bodies.velocity.size(), 0);
    for (const Joint& j : joints) loaded[j.a] = loaded[j.b] = kJoined;
    // Both bodies move, and the upper one is kLayerMassRatio times as heavy.
    auto heavyOver = [&](std::uint32_t up, std::uint32_t down) {
        const float upInverse = bodies.inverseMass[up];
        return upInverse > 0.0f && bodies.inverseMass[down] >= kLayerMassRatio * upInverse;
    };
    // Most steps have no pair of moving bodies this far apart in mass: nothing to do.
    // (The keys hold each row's bodies in 24 bytes, the normal rows in 144.)
    bool any = false;
    for (const ContactKey& k : contacts.keys)
        any = any || (!loaded[k.a] && !loaded[k.b] && (heavyOver(k.a, k.b) || heavyOver(k.b, k.a)));
    if (!any) return;
    std::vector<std::uint32_t>& layer = contacts.layer;
    findLayers(contacts, bodies, layer);
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        const NormalRow& r = contacts.normals[i];
        if (layer[r.a] != layer[r.b] && layer[r.a] != kNoLayer && layer[r.b] != kNoLayer &&
            loaded[r.a] != kJoined && loaded[r.b] != kJoined)
            rows.push_back(std::uint32_t(i));
    }
    auto lower = [&](std::uint32_t i) {
        return std::min(layer[contacts.normals[i].a], layer[contacts.normals[i].b]);
    };
    // From the top down: a row takes part when its upper body is kLayerMassRatio times as heavy
    // as its lower one, or carries such a load; its lower body then carries it.
    std::stable_sort(rows.begin(), rows.end(),
                     [&](std::uint32_t x, std::uint32_t y) { return lower(x) > lower(y); });
    std::size_t kept = 0;
    for (const std::uint32_t i : rows) {
        const NormalRow& r = contacts.normals[i];
        const bool upperIsB = layer[r.b] > layer[r.a];
        const std::uint32_t up = upperIsB ? r.b : r.a, down = upperIsB ? r.a : r.b;
        if (!heavyOver(up, down) && loaded[up] != kLoaded) continue;
        loaded[down] = kLoaded;
        rows[kept++] = i;
    }
    rows.resize(kept);
    // Then from the bottom up, each row stopping its upper body against the lower one.
    std::reverse(rows.begin(), rows.end());
    for (const std::uint32_t i : rows) {
        const NormalRow& r = contacts.normals[i];
        float total = r.impulse;
        solveNormalRowOnto(r, bodies.velocity[r.a], bodies.velocity[r.b], layer[r.b] > layer[r.a],
                           r.targetSpeed, total);
    }
}

namespace {

// The rows of an island are ordered by wave within blocks of this many (SweepRows): the blocks
// keep the bodies a stretch of rows touches few, and their velocities in the caches.
constexpr std::size_t kSweepBlock = 1024;

constexpr std::uint32_t kNoIsland = 0xffffffffu;

// The places in the sweeps' order (SweepOrder) of n rows, the j-th being ContactRows' row
// rowOf(j) (ascending): rows by island (numbered in the order of their first rows), then within
// each island's blocks by wave, stably. reads: keys (each row's bodies), bodies
// writes: s.place (by j), s.order (ContactRows' rows), s.islandStart, scratch
template <typename RowOf>
void orderSweepRows(const ContactRows& contacts, std::size_t n, RowOf rowOf,
                    const SolverBodies& bodies, SweepOrder& s) {
    const std::size_t bodyCount = bodies.velocity.size();
    // Islands: the rows joined through the moving bodies they share.
    s.islands.reset(bodyCount);
    for (std::size_t i = 0; i < n; ++i) {
        const ContactKey& k = contacts.keys[rowOf(i)];
        if (bodies.moves(k.a) && bodies.moves(k.b)) s.islands.unite(k.a, k.b);
    }
    std::vector<std::uint32_t>& byBody = s.byBody;
    byBody.assign(bodyCount, kNoIsland);
    s.place.resize(n);
    std::uint32_t islands = 0;
    // Each row's island, kept in place until the rows are listed by island.
    for (std::size_t i = 0; i < n; ++i) {
        const ContactKey& k = contacts.keys[rowOf(i)];
        const std::uint32_t root = s.islands.find(bodies.moves(k.a) ? k.a : k.b);
        if (byBody[root] == kNoIsland) byBody[root] = islands++;
        s.place[i] = byBody[root];
    }
    std::vector<std::uint32_t>& from = s.islandStart;
    from.assign(std::size_t(islands) + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++from[s.place[i] + 1];
    for (std::size_t j = 1; j < from.size(); ++j) from[j] += from[j - 1];
    std::vector<std::uint32_t>& rows = s.byIsland;
    rows.resize(n);
    std::vector<std::uint32_t>& next = s.waveStart;
    next.assign(from.begin(), from.end() - 1);
    for (std::size_t i = 0; i < n; ++i) rows[next[s.place[i]]++] = std::uint32_t(i);
    // Each row's wave, kept in place until the counting sort below turns it into a place; an
    // island's and a block's waves come after those before.
    std::vector<std::uint32_t>& last = byBody;
    last.assign(bodyCount, 0);
    std::uint32_t waves = 0, floor = 0;
    for (std::uint32_t j = 0; j < islands; ++j)
        for (std::size_t t = from[j]; t < from[j + 1]; ++t) {
            if ((t - from[j]) % kSweepBlock == 0) floor = waves;
            const std::uint32_t i = rows[t];
            const ContactKey& k = contacts.keys[rowOf(i)];
            const bool movesA = bodies.moves(k.a), movesB = bodies.moves(k.b);
            const std::uint32_t wave =
                std::max({floor, movesA ? last[k.a] : 0u, movesB ? last[k.b] : 0u}) + 1u;
            if (movesA) last[k.a] = wave;
            if (movesB) last[k.b] = wave;
            s.place[i] = wave;
            waves = std::max(waves, wave);
        }
    // A wave's rows lie in one island, in ContactRows' order.
    std::vector<std::uint32_t>& start = s.waveStart;
    start.assign(std::size_t(waves) + 2, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[s.place[i] + 1];
    for (std::size_t w = 1; w < start.size(); ++w) start[w] += start[w - 1];
    s.order.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        s.place[i] = start[s.place[i]]++;
        s.order[s.place[i]] = std::uint32_t(rowOf(i));
    }
}

} // namespace

void orderEveryRow(const ContactRows& contacts, const SolverBodies& bodies, SweepOrder& s) {
    orderSweepRows(
        contacts, contacts.size(), [](std::size_t i) { return i; }, bodies, s);
}

void packContactRows(ContactRows& contacts, SolverBodies& bodies, bool warmStart) {
    SweepRows& s = contacts.sweep;
    const std::size_t n = contacts.size();
    s.normals.resize(n);
    s.frictions.resize(n);
    s.normalImpulse.resize(n);
    orderEveryRow(contacts, bodies, s);
    // The packed rows are written in order, the full rows read where they are; the warm start
    // in the sweeps' order gives the same bits as in ContactRows' (SweepRows).
    for (std::size_t at = 0; at < n; ++at) {
        if (at + kPrefetchRows < n) {
            prefetchLines(contacts.normals[s.order[at + kPrefetchRows]]);
            prefetchLines(contacts.frictions[s.order[at + kPrefetchRows]]);
        }
        const std::uint32_t i = s.order[at];
        const NormalRow& r = contacts.normals[i];
        const FrictionRows& f = contacts.frictions[i];
        s.normals[at] = packNormal(r, r.targetSpeed);
        s.normalImpulse[at] = r.impulse;
        s.frictions[at] = packFriction(f);
        if (!warmStart) continue;
        SolverVelocity& a = bodies.velocity[r.a];
        SolverVelocity& b = bodies.velocity[r.b];
        if (r.impulse != 0.0f)
            applyRow(a, b, r.normal, r.turnA, r.turnB, r.inverseMassA, r.inverseMassB, r.impulse);
        for (int k = 0; k < 2; ++k)
            if (f.impulse[k] != 0.0f)
                applyRow(a, b, f.tangent[k], f.turnA[k], f.turnB[k], f.inverseMassA, f.inverseMassB,
                         f.impulse[k]);
    }
}

void unpackContactImpulses(ContactRows& contacts) {
    const SweepRows& s = contacts.sweep;
    const std::size_t n = contacts.size();
    // The packed rows read in order, the full rows written where they are: a store that misses
    // the caches does not hold up the loads behind it.
    for (std::size_t at = 0; at < n; ++at) {
        if (at + kPrefetchRows < n) {
            const std::uint32_t ahead = s.order[at + kPrefetchRows];
            __builtin_prefetch(&contacts.normals[ahead].impulse, 1);
            __builtin_prefetch(&contacts.frictions[ahead].impulse, 1);
        }
        const std::uint32_t i = s.order[at];
        contacts.normals[i].impulse = s.normalImpulse[at];
        FrictionRows& f = contacts.frictions[i];
        f.impulse[0] = s.frictions[at].crossB[0][3];
        f.impulse[1] = s.frictions[at].crossB[1][3];
    }
}

namespace {

// One sweep of packed normal rows [begin, end) on `velocity` (the bodies' velocities, or the
// split pass's push velocities), each toward the target in its crossA's fourth lane, from the
// accumulated impulses `impulse`, which stay >= 0; only the clamped change is applied. Returns the
// largest |applied change|, N s.
float sweepNormalRows(std::span<const SweepNormal> rows, float* impulse, std::size_t begin,
                      std::size_t end, SolverVelocity* velocity, const float* inverseMass,
                      float relaxation) {
    float residual = 0.0f;
    const std::size_t n = rows.size();
    for (std::size_t i = begin; i < end; ++i) {
        if (i + 2 * kPrefetchRows < n) prefetchLines(rows[i + 2 * kPrefetchRows]);
        if (i + kPrefetchRows < n) {
            const SweepNormal& ahead = rows[i + kPrefetchRows];
            __builtin_prefetch(&velocity[laneIndex(ahead.turnA[3])]);
            __builtin_prefetch(&velocity[laneIndex(ahead.turnB[3])]);
        }
        const SweepNormal& r = rows[i];
        const std::uint32_t ia = laneIndex(r.turnA[3]), ib = laneIndex(r.turnB[3]);
        SolverVelocity& a = velocity[ia];
        SolverVelocity& b = velocity[ib];
        float& accumulated = impulse[i];
        const float speed = rowSpeed(a, b, r.normal, r.crossA, r.crossB);
        const float total =
            std::max(accumulated + r.normal[3] * (r.crossA[3] - speed) * relaxation, 0.0f);
        const float applied = total - accumulated;
        accumulated = total;
        applyRow(a, b, xyz(r.normal), xyz(r.turnA), xyz(r.turnB), inverseMass[ia], inverseMass[ib],
                 applied);
        residual = std::max(residual, std::abs(applied));
    }
    return residual;
}

} // namespace

float solveContactSweep(SweepRows& rows, std::size_t begin, std::size_t end, SolverBodies& bodies,
                        float relaxation) {
    const std::size_t n = rows.normals.size();
    const float* inverseMass = bodies.inverseMass.data();
    SolverVelocity* velocity = bodies.velocity.data();
    // Every normal row first: the friction bounds then see this sweep's normal impulses.
    float residual = sweepNormalRows(rows.normals, rows.normalImpulse.data(), begin, end, velocity,
                                     inverseMass, relaxation);
    // Friction: a point's two tangent rows from the same velocities, each within the box
    // |lambda_t| <= mu lambda_n, applied together.
    for (std::size_t i = begin; i < end; ++i) {
        if (i + 2 * kPrefetchRows < n) prefetchLines(rows.frictions[i + 2 * kPrefetchRows]);
        if (i + kPrefetchRows < n) {
            const SweepFriction& ahead = rows.frictions[i + kPrefetchRows];
            __builtin_prefetch(&velocity[laneIndex(ahead.turnA[0][3])]);
            __builtin_prefetch(&velocity[laneIndex(ahead.turnA[1][3])]);
        }
        SweepFriction& r = rows.frictions[i];
        SolverVelocity& a = velocity[laneIndex(r.turnA[0][3])];
        SolverVelocity& b = velocity[laneIndex(r.turnA[1][3])];
        const float bound = r.turnB[0][3] * rows.normalImpulse[i];
        const Lanes dv = b.linear - a.linear;
        float applied[2];
        for (int k = 0; k < 2; ++k) {
            const float speed =
                sum3(r.tangent[k] * dv + r.crossB[k] * b.angular - r.crossA[k] * a.angular);
            const float change = -r.crossA[k][3] * speed * relaxation;
            const float before = r.crossB[k][3];
            const float total = std::clamp(before + change, -bound, bound);
            applied[k] = total - before;
            r.crossB[k][3] = total;
            residual = std::max(residual, std::abs(applied[k]));
        }
        const Lanes push = xyz(r.tangent[0]) * applied[0] + xyz(r.tangent[1]) * applied[1];
        a.linear -= push * r.tangent[0][3];
        a.angular -= xyz(r.turnA[0]) * applied[0] + xyz(r.turnA[1]) * applied[1];
        b.linear += push * r.tangent[1][3];
        b.angular += xyz(r.turnB[0]) * applied[0] + xyz(r.turnB[1]) * applied[1];
    }
    return residual;
}

bool solvePushes(ContactRows& contacts, SolverBodies& bodies, int iterations, float relaxation) {
    // The rows that push, and every row touching a body they move: contacts far from any
    // penetration would only watch.
    std::vector<std::uint8_t>& moved = contacts.pushedBody;
    moved.assign(bodies.velocity.size(), 0);
    bool needed = false;
    for (NormalRow& r : contacts.normals) {
        // A bounce that stops its bodies at the contact in this solve lifts them off it again.
        r.pushTarget = isBouncing(r) ? std::max(r.pushSpeed, r.bounceLift) : r.pushSpeed;
        if (r.pushTarget <= 0.0f) continue;
        needed = true;
        moved[r.a] = bodies.moves(r.a) ? 1 : 0;
        moved[r.b] = bodies.moves(r.b) ? 1 : 0;
    }
    if (!needed) return false;
    std::vector<std::uint32_t>& active = contacts.pushRows;
    active.clear();
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        NormalRow& r = contacts.normals[i];
        r.pushImpulse = 0.0f;
        if (r.pushTarget > 0.0f || moved[r.a] || moved[r.b]) active.push_back(std::uint32_t(i));
    }
    bodies.push.assign(bodies.velocity.size(), SolverVelocity{});
    // The rows packed as for the velocity sweeps, in their order (SweepRows: the same bits as in
    // `active`'s), each aiming at its push target.
    SweepRows& s = contacts.pushSweep;
    const std::size_t n = active.size();
    const auto activeRow = [&](std::size_t j) { return active[j]; };
    orderSweepRows(contacts, n, activeRow, bodies, s);
    s.normals.resize(n);
    s.normalImpulse.assign(n, 0.0f);
    for (std::size_t at = 0; at < n; ++at) {
        if (at + kPrefetchRows < n) prefetchLines(contacts.normals[s.order[at + kPrefetchRows]]);
        const NormalRow& r = contacts.normals[s.order[at]];
        s.normals[at] = packNormal(r, r.pushTarget);
    }
    for (int it = 0; it < iterations; ++it) {
        const float residual =
            sweepNormalRows(s.normals, s.normalImpulse.data(), 0, n, bodies.push.data(),
                            bodies.inverseMass.data(), relaxation);
        // Converged: a further sweep would move nothing by more than round-off.
        if (residual <= kPushTolerance) break;
    }
    for (std::size_t at = 0; at < n; ++at)
        contacts.normals[s.order[at]].pushImpulse = s.normalImpulse[at];
    // The layer pass's rows (solvePgs), bottom up, each moving its upper body only.
    for (const std::uint32_t i : contacts.layerRows) {
        const NormalRow& r = contacts.normals[i];
        if (r.pushTarget <= 0.0f && !moved[r.a] && !moved[r.b]) continue;
        float total = r.pushImpulse;
        solveNormalRowOnto(r, bodies.push[r.a], bodies.push[r.b],
                           contacts.layer[r.b] > contacts.layer[r.a], r.pushTarget, total);
    }
    return true;
}

bool solveRestitution(ContactRows& contacts, SolverBodies& bodies, int iterations) {
    std::vector<std::uint32_t>& rows = contacts.bounceRows;
    rows.clear();
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        NormalRow& r = contacts.normals[i];
        r.bounceImpulse = 0.0f;
        if (isBouncing(r)) rows.push_back(std::uint32_t(i));
    }
    if (rows.empty()) return false;
    for (int it = 0; it < iterations; ++it) {
        float residual = 0.0f;
        for (const std::uint32_t i : rows) {
            NormalRow& r = contacts.normals[i];
            SolverVelocity& a = bodies.velocity[r.a];
            SolverVelocity& b = bodies.velocity[r.b];
            const float speed = rowSpeed(a, b, r.normal, r.crossA, r.crossB);
            const float total =
                std::max(r.bounceImpulse + r.mass * (r.bounceSpeed - speed), -r.impulse);
            const float applied = total - r.bounceImpulse;
            r.bounceImpulse = total;
            applyRow(a, b, r.normal, r.turnA, r.turnB, r.inverseMassA, r.inverseMassB, applied);
            residual = std::max(residual, std::abs(applied));
        }
        if (residual <= kPushTolerance) break;
    }
    return true;
}

void addBounceImpulses(const ContactRows& contacts, std::span<shared::BodyMomentum> momenta) {
    for (const std::uint32_t i : contacts.bounceRows) {
        const NormalRow& r = contacts.normals[i];
        const Lanes linear = r.normal * r.bounceImpulse;
        // A body that does not move has zero crosses and takes nothing.
        if (r.inverseMassA > 0.0f) {
            shared::BodyMomentum& p = momenta[r.a];
            p.linear = toFloat4(toVec3(p.linear) - fromLanes(linear));
            p.angular = toFloat4(toVec3(p.angular) - fromLanes(r.crossA * r.bounceImpulse));
        }
        if (r.inverseMassB > 0.0f) {
            shared::BodyMomentum& p = momenta[r.b];
            p.linear = toFloat4(toVec3(p.linear) + fromLanes(linear));
            p.angular = toFloat4(toVec3(p.angular) + fromLanes(r.crossB * r.bounceImpulse));
        }
    }
}

void solvePgs(ContactRows& contacts, std::span<Joint> joints, SolverBodies& bodies,
              const SolverOptions& options, std::vector<float>& residuals) {
    if (options.warmStart) warmStartJoints(joints, bodies);
    packContactRows(contacts, bodies, options.warmStart);
    residuals.assign(std::size_t(std::max(options.iterations, 0)), 0.0f);
    SweepRows& rows = contacts.sweep;
    const std::vector<std::uint32_t>& island = rows.islandStart;
    if (joints.empty()) {
        // Islands share no moving body: each one's sweeps alone give the same bits, and a small
        // island's rows stay in the caches from one sweep to the next.
        for (std::size_t j = 0; j + 1 < island.size(); ++j)
            for (float& residual : residuals)
                residual = std::max(residual, solveContactSweep(rows, island[j], island[j + 1],
                                                                bodies, options.relaxation));
    } else {
        for (float& residual : residuals) {
            for (Joint& j : joints)
                residual = std::max(residual, solveJointVelocity(j, bodies, options.relaxation));
            residual = std::max(
                residual, solveContactSweep(rows, 0, contacts.size(), bodies, options.relaxation));
        }
    }
    unpackContactImpulses(contacts);
    solveLayers(contacts, joints, bodies);
}

} // namespace rubble
