// host/dynamics/soft_step.cpp: CPU stage 6 of the soft-step solver: substeps with soft contacts
// and joints, relax passes, restitution.
#include "host/dynamics/soft_step.h"

#include <algorithm>
#include <cmath>

#include "host/core/math.h"
#include "host/dynamics/joint_rows.h"
#include "host/dynamics/pgs.h"

namespace rubble {
namespace {

constexpr float kPi = 3.14159265358979f;

// A contact against a body that does not move takes this many times the contact hertz (Box2D
// v3's static softness: nothing on the other side gives way).
constexpr float kStillContactHertzScale = 2.0f;

Lanes rotateLanes(shared::float4 q, glm::vec3 v) {
    return toLanes(toVec3(shared::quatRotate(q, toFloat4(v))));
}

// A normal row's settings in a pass: the bias speed (m/s), the mass and impulse scales.
struct PointSoftness {
    float bias = 0.0f, massScale = 1.0f, impulseScale = 0.0f;
};

// A point's separation now: the start's, moved by the bodies' motion within the step.
float separationNow(const SoftAnchors& p, const SoftPoses& poses) {
    const std::uint32_t a = laneIndex(p.anchorA[3]), b = laneIndex(p.anchorB[3]);
    const Lanes pointA =
        poses.moved[a] + rotateLanes(poses.pose[a].orientation, fromLanes(p.anchorA));
    const Lanes pointB =
        poses.moved[b] + rotateLanes(poses.pose[b].orientation, fromLanes(p.anchorB));
    return p.normal[3] + sum3(p.normal * ((pointB - p.offsetB) - (pointA - p.offsetA)));
}

// A gap (separation > 0) is closed within the substep and no further, rigidly; an overlap is
// pushed out by the point's spring (biased pass) or held rigidly (relax pass).
PointSoftness pointSoftness(float biasRate, float massScale, float impulseScale, float separation,
                            float inverseH, const SoftStepSettings& s, bool useBias) {
    PointSoftness k;
    if (separation > 0.0f) {
        k.bias = separation * inverseH;
    } else if (useBias) {
        k.bias = std::max(biasRate * separation, -s.maxPushSpeed);
        k.massScale = massScale;
        k.impulseScale = impulseScale;
    }
    return k;
}

// Whether a manifold is a landing: one of its points was a gap at the step's start (a
// speculative point) and approached faster than the restitution threshold (the speed at which
// Box2D v3's restitution tells a hit from a touch).
bool isLanding(std::span<const SoftContactPoint> points, const SoftManifold& m, float threshold) {
    for (std::uint32_t k = 0; k < m.count; ++k) {
        const SoftContactPoint& p = points[m.rows[k]];
        if (p.separation > 0.0f && p.relativeVelocity < -threshold) return true;
    }
    return false;
}

// Sets each point's spring, and puts the rows and points into the passes' packed form
// (SoftPassRows, in the sweeps' order), with the landings that solveManifoldNormals takes (two or
// more points).
void packSoftRows(const ContactRows& rows, std::span<SoftContactPoint> points,
                  std::span<const SoftManifold> pointManifolds, const SolverBodies& bodies,
                  const SoftStepSettings& s, SoftPassRows& packed) {
    const std::size_t n = rows.size();
    orderEveryRow(rows, bodies, packed.order);
    packed.normals.resize(n);
    packed.frictions.resize(n);
    packed.anchors.resize(n);
    packed.state.resize(n);
    for (std::size_t at = 0; at < n; ++at) {
        const std::uint32_t i = packed.order.order[at];
        if (at + kPrefetchRows < n) {
            const std::uint32_t ahead = packed.order.order[at + kPrefetchRows];
            prefetchLines(rows.normals[ahead]);
            prefetchLines(rows.frictions[ahead]);
            prefetchLines(points[ahead]);
        }
        const NormalRow& r = rows.normals[i];
        const FrictionRows& f = rows.frictions[i];
        SoftContactPoint& p = points[i];
        p.soft = softnessFor(s.contactHertz, s.dampingRatio, s.h, r.inverseMassA, r.inverseMassB,
                             kStillContactHertzScale);
        SoftNormal& q = packed.normals[at];
        q.normal = r.normal;
        q.normal[3] = r.mass;
        q.crossA = r.crossA;
        q.crossA[3] = p.soft.biasRate;
        q.crossB = r.crossB;
        q.crossB[3] = p.soft.massScale;
        q.turnA = r.turnA;
        q.turnA[3] = indexLane(r.a);
        q.turnB = r.turnB;
        q.turnB[3] = indexLane(r.b);
        packed.frictions[at] = packFriction(f);
        SoftAnchors& c = packed.anchors[at];
        c.normal = r.normal;
        c.normal[3] = p.separation;
        c.offsetA = p.offsetA;
        c.offsetB = p.offsetB;
        c.anchorA = toLanes(p.anchorA);
        c.anchorA[3] = indexLane(r.a);
        c.anchorB = toLanes(p.anchorB);
        c.anchorB[3] = indexLane(r.b);
        packed.state[at] = SoftPointState{0.0f, p.soft.impulseScale, r.impulse, p.maxNormalImpulse};
    }
    packed.landings.clear();
    for (std::size_t m = 0; m < pointManifolds.size(); ++m)
        if (pointManifolds[m].count >= 2 &&
            isLanding(points, pointManifolds[m], s.restitutionThreshold))
            packed.landings.push_back(std::uint32_t(m));
}

// The passes' impulses back into the rows and points, the packed rows read in order (as
// unpackContactImpulses).
void unpackSoftRows(const SoftPassRows& packed, ContactRows& rows,
                    std::span<SoftContactPoint> points) {
    const std::size_t n = rows.size();
    for (std::size_t at = 0; at < n; ++at) {
        if (at + kPrefetchRows < n) {
            const std::uint32_t ahead = packed.order.order[at + kPrefetchRows];
            __builtin_prefetch(&rows.normals[ahead].impulse, 1);
            __builtin_prefetch(&rows.frictions[ahead].impulse, 1);
            __builtin_prefetch(&points[ahead].maxNormalImpulse, 1);
        }
        const std::uint32_t i = packed.order.order[at];
        rows.normals[i].impulse = packed.state[at].impulse;
        points[i].maxNormalImpulse = packed.state[at].maxNormalImpulse;
        FrictionRows& f = rows.frictions[i];
        f.impulse[0] = packed.frictions[at].crossB[0][3];
        f.impulse[1] = packed.frictions[at].crossB[1][3];
    }
}

// Each island's moving bodies and landings (a landing's island is its first point's), and the
// bodies of no island, into `packed` (SoftPassRows).
void groupIslands(const ContactRows& rows, std::span<const SoftManifold> pointManifolds,
                  const SolverBodies& bodies, SoftPassRows& packed) {
    const SweepOrder& o = packed.order;
    const std::size_t islands = o.islandStart.size() - 1;
    std::vector<std::uint8_t>& grouped = packed.grouped;
    grouped.assign(bodies.velocity.size(), 0);
    packed.islandBodies.clear();
    packed.islandBodyStart.assign(1, 0);
    for (std::size_t j = 0; j < islands; ++j) {
        for (std::size_t at = o.islandStart[j]; at < o.islandStart[j + 1]; ++at) {
            const NormalRow& r = rows.normals[o.order[at]];
            for (const std::uint32_t body : {r.a, r.b}) {
                if (!bodies.moves(body) || grouped[body]) continue;
                grouped[body] = 1;
                packed.islandBodies.push_back(body);
            }
        }
        packed.islandBodyStart.push_back(std::uint32_t(packed.islandBodies.size()));
    }
    packed.otherBodies.clear();
    for (std::size_t i = 0; i < grouped.size(); ++i)
        if (!grouped[i]) packed.otherBodies.push_back(std::uint32_t(i));
    // The landings by island, in manifold order within each.
    const auto islandOf = [&](std::uint32_t m) {
        const std::uint32_t at = o.place[pointManifolds[m].rows[0]];
        return std::size_t(std::upper_bound(o.islandStart.begin(), o.islandStart.end(), at) -
                           o.islandStart.begin() - 1);
    };
    std::vector<std::uint32_t>& start = packed.islandLandingStart;
    start.assign(islands + 1, 0);
    for (const std::uint32_t m : packed.landings) ++start[islandOf(m) + 1];
    for (std::size_t j = 1; j < start.size(); ++j) start[j] += start[j - 1];
    packed.islandLandings.resize(packed.landings.size());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (const std::uint32_t m : packed.landings) packed.islandLandings[fill[islandOf(m)]++] = m;
}

// One update of a landing's normal rows together, along the direction that adds the same
// impulse to every point (a push at the points' centroid): the exact minimum along it of the
// quadratic that the point updates minimise one row at a time (each point's spring a diagonal
// term impulseScale / (massScale m_eff)), kept where no point's impulse goes below 0. One
// Gauss-Seidel pass over a face's points alone gives the first point more than its share of the
// hit and turns the body, and the next substep's warm start applies that share again; this
// update stops all of them at once, so that a face that lands flat stays flat. Contacts that
// were touching at the step's start are left to the point updates, which their warm start
// carries. The impulses are the packed ones, and so are the separations unless `moved` (the
// poses, when they moved since the separations were found). Returns the |applied change| per
// point, N s.
float solveManifoldNormals(const ContactRows& rows, std::span<const SoftContactPoint> points,
                           const SoftManifold& m, SoftPassRows& packed, SolverBodies& bodies,
                           const SoftPoses* moved, const SoftStepSettings& s, bool useBias) {
    const float inverseH = 1.0f / s.h;
    const NormalRow& first = rows.normals[m.rows[0]];
    SolverVelocity& a = bodies.velocity[first.a];
    SolverVelocity& b = bodies.velocity[first.b];
    const std::vector<std::uint32_t>& place = packed.order.place;
    float slope = 0.0f, diagonal = 0.0f, lowest = packed.state[place[m.rows[0]]].impulse;
    Lanes crossA{}, turnA{}, crossB{}, turnB{};
    for (std::uint32_t k = 0; k < m.count; ++k) {
        const NormalRow& r = rows.normals[m.rows[k]];
        const Softness& spring = points[m.rows[k]].soft;
        const SoftPointState& p = packed.state[place[m.rows[k]]];
        const float separation =
            moved ? separationNow(packed.anchors[place[m.rows[k]]], *moved) : p.separation;
        const PointSoftness soft =
            pointSoftness(spring.biasRate, spring.massScale, spring.impulseScale, separation,
                          inverseH, s, useBias);
        const float diagonalTerm = soft.impulseScale / (soft.massScale * r.mass);
        slope +=
            rowSpeed(a, b, r.normal, r.crossA, r.crossB) + soft.bias + diagonalTerm * p.impulse;
        diagonal += diagonalTerm;
        lowest = std::min(lowest, p.impulse);
        crossA += r.crossA;
        turnA += r.turnA;
        crossB += r.crossB;
        turnB += r.turnB;
    }
    const float n = float(m.count);
    const float curvature = n * n * (first.inverseMassA + first.inverseMassB) +
                            sum3(crossA * turnA) + sum3(crossB * turnB) + diagonal;
    if (!(curvature > 0.0f)) return 0.0f;
    const float change = std::max(-slope / curvature, -lowest);
    for (std::uint32_t k = 0; k < m.count; ++k) {
        SoftPointState& p = packed.state[place[m.rows[k]]];
        p.impulse += change;
        p.maxNormalImpulse = std::max(p.maxNormalImpulse, p.impulse);
    }
    a.linear -= first.normal * (first.inverseMassA * (n * change));
    a.angular -= turnA * change;
    b.linear += first.normal * (first.inverseMassB * (n * change));
    b.angular += turnB * change;
    return std::abs(change);
}

// The normal rows of each of `landings` together (solveManifoldNormals), in manifold order.
// Returns the largest |applied change| per point, N s.
float solveManifolds(const ContactRows& rows, std::span<const SoftContactPoint> points,
                     std::span<const SoftManifold> pointManifolds,
                     std::span<const std::uint32_t> landings, SoftPassRows& packed,
                     SolverBodies& bodies, const SoftPoses* moved, const SoftStepSettings& s,
                     bool useBias) {
    float residual = 0.0f;
    for (const std::uint32_t m : landings)
        residual = std::max(residual, solveManifoldNormals(rows, points, pointManifolds[m], packed,
                                                           bodies, moved, s, useBias));
    return residual;
}

// Asks for what a pass over the points reads soon after point i: the packed rows (and, with
// `moved`, the anchors) of the point kPrefetchRows further on than the next, and the velocities
// (and, with `moved`, the poses) of the bodies of the point kPrefetchRows on.
void prefetchAhead(const SoftPassRows& packed, const SolverVelocity* velocity,
                   const SoftPoses* moved, std::size_t i) {
    const std::size_t n = packed.normals.size();
    if (i + 2 * kPrefetchRows < n) {
        prefetchLines(packed.normals[i + 2 * kPrefetchRows]);
        prefetchLines(packed.frictions[i + 2 * kPrefetchRows]);
        if (moved) prefetchLines(packed.anchors[i + 2 * kPrefetchRows]);
    }
    if (i + kPrefetchRows >= n) return;
    const SoftNormal& ahead = packed.normals[i + kPrefetchRows];
    for (const float lane : {ahead.turnA[3], ahead.turnB[3]}) {
        __builtin_prefetch(&velocity[laneIndex(lane)]);
        if (!moved) continue;
        __builtin_prefetch(&moved->moved[laneIndex(lane)]);
        __builtin_prefetch(&moved->pose[laneIndex(lane)]);
    }
}

// One pass over the packed contact points [begin, end): each point's normal row (soft with
// bias, rigid without; a gap is closed within the substep and no further), then its two friction
// rows within |lambda_t| <= mu lambda_n. With `moved` (the poses, when they moved since the
// separations were found) each point's separation is found first and kept for the passes until
// the next move: the poses change only there. Returns the largest |applied change|, N s.
float solveContacts(SoftPassRows& packed, std::size_t begin, std::size_t end, SolverBodies& bodies,
                    const SoftPoses* moved, const SoftStepSettings& s, bool useBias) {
    float residual = 0.0f;
    const float inverseH = 1.0f / s.h;
    const float* inverseMass = bodies.inverseMass.data();
    SolverVelocity* velocity = bodies.velocity.data();
    for (std::size_t i = begin; i < end; ++i) {
        prefetchAhead(packed, velocity, moved, i);
        const SoftNormal& r = packed.normals[i];
        SoftPointState& p = packed.state[i];
        if (moved) p.separation = separationNow(packed.anchors[i], *moved);
        const std::uint32_t ia = laneIndex(r.turnA[3]), ib = laneIndex(r.turnB[3]);
        SolverVelocity& a = velocity[ia];
        SolverVelocity& b = velocity[ib];
        const PointSoftness soft = pointSoftness(r.crossA[3], r.crossB[3], p.impulseScale,
                                                 p.separation, inverseH, s, useBias);
        const float speed = rowSpeed(a, b, r.normal, r.crossA, r.crossB);
        const float change =
            -r.normal[3] * soft.massScale * (speed + soft.bias) - soft.impulseScale * p.impulse;
        const float total = std::max(p.impulse + change, 0.0f);
        const float applied = total - p.impulse;
        p.impulse = total;
        p.maxNormalImpulse = std::max(p.maxNormalImpulse, total);
        applyRow(a, b, xyz(r.normal), xyz(r.turnA), xyz(r.turnB), inverseMass[ia], inverseMass[ib],
                 applied);
        residual = std::max(residual, std::abs(applied));

        SweepFriction& f = packed.frictions[i];
        const float bound = f.turnB[0][3] * p.impulse;
        for (int k = 0; k < 2; ++k) {
            const float tangentSpeed = rowSpeed(a, b, f.tangent[k], f.crossA[k], f.crossB[k]);
            const float before = f.crossB[k][3];
            const float next = std::clamp(before - f.crossA[k][3] * tangentSpeed, -bound, bound);
            const float step = next - before;
            f.crossB[k][3] = next;
            applyRow(a, b, xyz(f.tangent[k]), xyz(f.turnA[k]), xyz(f.turnB[k]), f.tangent[0][3],
                     f.tangent[1][3], step);
            residual = std::max(residual, std::abs(step));
        }
    }
    return residual;
}

void warmStartContacts(const SoftPassRows& packed, std::size_t begin, std::size_t end,
                       SolverBodies& bodies) {
    const float* inverseMass = bodies.inverseMass.data();
    SolverVelocity* velocity = bodies.velocity.data();
    for (std::size_t i = begin; i < end; ++i) {
        prefetchAhead(packed, velocity, nullptr, i);
        const SoftNormal& r = packed.normals[i];
        const std::uint32_t ia = laneIndex(r.turnA[3]), ib = laneIndex(r.turnB[3]);
        SolverVelocity& a = velocity[ia];
        SolverVelocity& b = velocity[ib];
        applyRow(a, b, xyz(r.normal), xyz(r.turnA), xyz(r.turnB), inverseMass[ia], inverseMass[ib],
                 packed.state[i].impulse);
        const SweepFriction& f = packed.frictions[i];
        for (int k = 0; k < 2; ++k)
            applyRow(a, b, xyz(f.tangent[k]), xyz(f.turnA[k]), xyz(f.turnB[k]), f.tangent[0][3],
                     f.tangent[1][3], f.crossB[k][3]);
    }
}

// A joint's arms at the bodies' current orientations.
void jointArms(const Joint& j, const SoftPoses& poses, glm::vec3& ra, glm::vec3& rb) {
    ra = toVec3(shared::quatRotate(poses.pose[j.a].orientation, toFloat4(j.anchorA)));
    rb = toVec3(shared::quatRotate(poses.pose[j.b].orientation, toFloat4(j.anchorB)));
}

void warmStartJoints(std::span<const Joint> joints, const SoftPoses& poses, SolverBodies& bodies) {
    for (const Joint& j : joints) {
        if (!j.active) continue;
        glm::vec3 ra, rb;
        jointArms(j, poses, ra, rb);
        applyPointImpulse(j, ra, rb, j.pointImpulse, bodies);
        if (j.type != JointType::Hinge) continue;
        glm::vec3 turn[2];
        hingeRows(j, poses.pose[j.a], poses.pose[j.b], turn, nullptr);
        applyTurnImpulse(j, turn, j.turnImpulse, bodies);
    }
}

// One pass over the joints: the hinge's two angular rows as a 2x2 block, then the anchor's
// three rows as a 3x3 block, at the bodies' current poses; soft toward C = 0 with bias, rigid
// on C' = 0 without. Returns the largest |applied change|, N s.
float solveJoints(std::span<Joint> joints, SolverBodies& bodies, const SoftPoses& poses,
                  std::span<const Softness> softness, bool useBias) {
    float residual = 0.0f;
    for (std::size_t n = 0; n < joints.size(); ++n) {
        Joint& j = joints[n];
        if (!j.active) continue;
        const Softness& soft = softness[n];
        const float massScale = useBias ? soft.massScale : 1.0f;
        const float impulseScale = useBias ? soft.impulseScale : 0.0f;
        const float biasRate = useBias ? soft.biasRate : 0.0f;
        const glm::mat3& ia = bodies.inverseInertia[j.a];
        const glm::mat3& ib = bodies.inverseInertia[j.b];
        if (j.type == JointType::Hinge) {
            glm::vec3 turn[2];
            glm::vec2 c;
            hingeRows(j, poses.pose[j.a], poses.pose[j.b], turn, &c);
            const glm::mat2 mass = safeInverse(hingeMatrix(turn, ia, ib));
            const glm::vec3 dw =
                fromLanes(bodies.velocity[j.a].angular) - fromLanes(bodies.velocity[j.b].angular);
            const glm::vec2 speed(glm::dot(turn[0], dw), glm::dot(turn[1], dw));
            const glm::vec2 impulse =
                -massScale * (mass * (speed + biasRate * c)) - impulseScale * j.turnImpulse;
            j.turnImpulse += impulse;
            applyTurnImpulse(j, turn, impulse, bodies);
            residual = std::max(residual, std::max(std::abs(impulse.x), std::abs(impulse.y)));
        }
        glm::vec3 ra, rb;
        jointArms(j, poses, ra, rb);
        const SolverVelocity& a = bodies.velocity[j.a];
        const SolverVelocity& b = bodies.velocity[j.b];
        const glm::vec3 speed = (fromLanes(b.linear) + glm::cross(fromLanes(b.angular), rb)) -
                                (fromLanes(a.linear) + glm::cross(fromLanes(a.angular), ra));
        const glm::vec3 separation =
            (toVec3(poses.pose[j.b].position) + rb) - (toVec3(poses.pose[j.a].position) + ra);
        const glm::mat3 k =
            pointMatrix(ra, rb, bodies.inverseMass[j.a], bodies.inverseMass[j.b], ia, ib);
        const glm::vec3 impulse = -massScale * (safeInverse(k) * (speed + biasRate * separation)) -
                                  impulseScale * j.pointImpulse;
        j.pointImpulse += impulse;
        applyPointImpulse(j, ra, rb, impulse, bodies);
        const glm::vec3 size = glm::abs(impulse);
        residual = std::max(residual, std::max(size.x, std::max(size.y, size.z)));
    }
    return residual;
}

// x += h v, q turned by h w, for those of `which` that move.
void movePoses(const SolverBodies& bodies, std::span<const std::uint32_t> which, float h,
               SoftPoses& poses) {
    for (const std::uint32_t i : which) {
        if (!bodies.moves(i)) continue;
        const SolverVelocity& v = bodies.velocity[i];
        const Lanes step = v.linear * h;
        poses.moved[i] += step;
        shared::BodyPose& pose = poses.pose[i];
        pose.position = toFloat4(toVec3(pose.position) + fromLanes(step));
        pose.orientation =
            shared::quatIntegrate(pose.orientation, toFloat4(fromLanes(v.angular)), h);
    }
}

// A part of the step that runs its substeps on its own: the packed points [begin, end), their
// landings, the bodies that take the forces' share and move, and the joints.
struct SoftGroup {
    std::size_t begin = 0, end = 0;
    std::span<const std::uint32_t> landings; ///< pointManifolds' indices
    std::span<const std::uint32_t> bodies;
    std::span<Joint> joints;
    std::span<const Softness> jointSoftness;
};

// The substeps of one part of the step (SoftGroup): each substep its share of the forces, the
// warm start, a biased pass, the move, then the relax passes. Each pass's largest |applied
// change| raises `residuals` (one per pass, N s).
void runSubsteps(const SoftGroup& g, const ContactRows& rows,
                 std::span<const SoftContactPoint> points,
                 std::span<const SoftManifold> pointManifolds,
                 std::span<const SolverVelocity> forcesShare, SolverBodies& bodies,
                 const SoftStepSettings& s, SoftPoses& poses, SoftPassRows& packed,
                 std::span<float> residuals) {
    // The poses, while the points' separations have not been found since they moved.
    const SoftPoses* moved = &poses;
    std::size_t pass = 0;
    const auto keep = [&](float residual) {
        residuals[pass] = std::max(residuals[pass], residual);
        ++pass;
    };
    for (int sub = 0; sub < s.substeps; ++sub) {
        for (const std::uint32_t i : g.bodies) {
            bodies.velocity[i].linear += forcesShare[i].linear;
            bodies.velocity[i].angular += forcesShare[i].angular;
        }
        warmStartJoints(g.joints, poses, bodies);
        warmStartContacts(packed, g.begin, g.end, bodies);
        float residual = solveManifolds(rows, points, pointManifolds, g.landings, packed, bodies,
                                        moved, s, true);
        residual = std::max(residual, solveJoints(g.joints, bodies, poses, g.jointSoftness, true));
        residual =
            std::max(residual, solveContacts(packed, g.begin, g.end, bodies, moved, s, true));
        moved = nullptr;
        keep(residual);
        movePoses(bodies, g.bodies, s.h, poses);
        moved = &poses;
        for (int k = 0; k < s.relaxIterations; ++k) {
            float relaxed = solveManifolds(rows, points, pointManifolds, g.landings, packed, bodies,
                                           moved, s, false);
            relaxed =
                std::max(relaxed, solveJoints(g.joints, bodies, poses, g.jointSoftness, false));
            relaxed =
                std::max(relaxed, solveContacts(packed, g.begin, g.end, bodies, moved, s, false));
            moved = nullptr;
            keep(relaxed);
        }
    }
}

// Restitution after the substeps (Box2D v3's b2ApplyRestitution): a point that approached faster
// than the threshold before the step and pushed in a substep leaves at -e times that speed.
void applyRestitution(ContactRows& rows, std::span<SoftContactPoint> points, SolverBodies& bodies,
                      float threshold) {
    for (std::size_t i = 0; i < rows.size(); ++i) {
        SoftContactPoint& p = points[i];
        if (p.restitution == 0.0f || p.relativeVelocity > -threshold || p.maxNormalImpulse == 0.0f)
            continue;
        NormalRow& r = rows.normals[i];
        SolverVelocity& a = bodies.velocity[r.a];
        SolverVelocity& b = bodies.velocity[r.b];
        const float speed = rowSpeed(a, b, r.normal, r.crossA, r.crossB);
        const float change = -r.mass * (speed + p.restitution * p.relativeVelocity);
        const float total = std::max(r.impulse + change, 0.0f);
        applyRow(a, b, r.normal, r.turnA, r.turnB, r.inverseMassA, r.inverseMassB,
                 total - r.impulse);
        r.impulse = total;
        p.maxNormalImpulse = std::max(p.maxNormalImpulse, total);
    }
}

} // namespace

Softness softnessFor(float hertz, float dampingRatio, float h, float ima, float imb,
                     float againstStill) {
    if (ima == 0.0f || imb == 0.0f) return makeSoftness(againstStill * hertz, dampingRatio, h);
    return makeSoftness(hertz, dampingRatio, h);
}

Softness makeSoftness(float hertz, float dampingRatio, float h) {
    if (hertz == 0.0f) return Softness{};
    const float omega = 2.0f * kPi * hertz;
    const float a1 = 2.0f * dampingRatio + h * omega;
    const float a2 = h * omega * a1;
    const float a3 = 1.0f / (1.0f + a2);
    return Softness{omega / a1, a2 * a3, a3};
}

SoftStepSettings makeSoftStepSettings(const SolverOptions& o, float dt) {
    SoftStepSettings s;
    s.substeps = std::max(o.substeps, 1);
    s.relaxIterations = std::max(o.relaxIterations, 0);
    s.h = dt / float(s.substeps);
    const float hertz = std::min(o.contactHertz, 0.25f / s.h);
    s.contactHertz = hertz;
    s.dampingRatio = o.dampingRatio;
    s.jointHertz = o.jointHertz;
    s.jointDampingRatio = o.jointDampingRatio;
    s.maxPushSpeed = o.maxPushSpeed;
    s.restitutionThreshold = RUBBLE_RESTITUTION_THRESHOLD;
    s.warmStart = o.warmStart;
    return s;
}

void prepareSoftContacts(std::span<const Manifold> manifolds, const ContactRows& rows,
                         std::span<const shared::BodyPose> poses, const SolverBodies& bodies,
                         std::span<const shared::BodyVelocity> approach,
                         std::span<const MaterialDesc> materials,
                         std::span<const std::uint32_t> materialOf,
                         std::span<const BodyPair> joined, std::vector<SoftContactPoint>& points,
                         std::vector<SoftManifold>& pointManifolds) {
    // The points in the order buildContactRows read them (before its interleaving).
    std::vector<SoftContactPoint> inOrder;
    inOrder.reserve(rows.size());
    pointManifolds.clear();
    for (const Manifold& m : manifolds) {
        if (m.count == 0) continue;
        if (!bodies.moves(m.a) && !bodies.moves(m.b)) continue;
        if (isJoinedPair(joined, m.a, m.b)) continue;
        const float restitution = std::max(materials[materialOf[m.a]].restitution,
                                           materials[materialOf[m.b]].restitution);
        const shared::BodyPose& pa = poses[m.a];
        const shared::BodyPose& pb = poses[m.b];
        const glm::vec3 xa = toVec3(pa.position), xb = toVec3(pb.position);
        const shared::BodyVelocity& va = approach[m.a];
        const shared::BodyVelocity& vb = approach[m.b];
        SoftManifold group;
        group.count = m.count;
        for (std::uint32_t k = 0; k < m.count; ++k)
            group.rows[k] = std::uint32_t(inOrder.size() + k);
        pointManifolds.push_back(group);
        for (std::uint32_t k = 0; k < m.count; ++k) {
            const ContactPoint& c = m.points[k];
            SoftContactPoint p;
            const glm::vec3 ra = c.position - xa, rb = c.position - xb;
            p.offsetA = toLanes(ra);
            p.offsetB = toLanes(rb);
            p.anchorA = toVec3(shared::quatRotateInverse(pa.orientation, toFloat4(ra)));
            p.anchorB = toVec3(shared::quatRotateInverse(pb.orientation, toFloat4(rb)));
            p.separation = -c.depth;
            const glm::vec3 pointA = toVec3(va.linear) + glm::cross(toVec3(va.angular), ra);
            const glm::vec3 pointB = toVec3(vb.linear) + glm::cross(toVec3(vb.angular), rb);
            p.relativeVelocity = glm::dot(m.normal, pointB - pointA);
            p.restitution = restitution;
            inOrder.push_back(p);
        }
    }
    points.resize(rows.size());
    std::vector<std::uint32_t> rowOf(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::uint32_t at = rows.built.empty() ? std::uint32_t(i) : rows.built[i];
        points[i] = inOrder[at];
        rowOf[at] = std::uint32_t(i);
    }
    // The manifolds' points by their rows' indices.
    for (SoftManifold& group : pointManifolds)
        for (std::uint32_t k = 0; k < group.count; ++k) group.rows[k] = rowOf[group.rows[k]];
}

void solveSoftStep(ContactRows& rows, std::span<SoftContactPoint> points,
                   std::span<const SoftManifold> pointManifolds, std::span<Joint> joints,
                   SolverBodies& bodies, std::span<const shared::BodyVelocity> start,
                   std::span<const shared::BodyVelocity> afterForces, const SoftStepSettings& s,
                   SoftPoses& poses, SoftPassRows& packed, std::vector<float>& residuals) {
    const std::size_t n = bodies.velocity.size();
    // Each substep takes its share of the forces' velocity change.
    std::vector<SolverVelocity> forcesShare(n);
    const float share = 1.0f / float(s.substeps);
    for (std::size_t i = 0; i < n; ++i) {
        if (!bodies.moves(std::uint32_t(i))) continue;
        const Lanes v0 = toLanes(toVec3(start[i].linear)), w0 = toLanes(toVec3(start[i].angular));
        forcesShare[i].linear = (toLanes(toVec3(afterForces[i].linear)) - v0) * share;
        forcesShare[i].angular = (toLanes(toVec3(afterForces[i].angular)) - w0) * share;
        bodies.velocity[i] = SolverVelocity{v0, w0};
    }
    if (!s.warmStart) {
        for (NormalRow& r : rows.normals) r.impulse = 0.0f;
        for (FrictionRows& f : rows.frictions) f.impulse[0] = f.impulse[1] = 0.0f;
        for (Joint& j : joints) {
            j.pointImpulse = glm::vec3(0.0f);
            j.turnImpulse = glm::vec2(0.0f);
        }
    }
    // Each constraint's spring (the contacts' in packSoftRows).
    std::vector<Softness> jointSoftness(joints.size());
    for (std::size_t i = 0; i < joints.size(); ++i)
        jointSoftness[i] =
            softnessFor(s.jointHertz, s.jointDampingRatio, s.h, bodies.inverseMass[joints[i].a],
                        bodies.inverseMass[joints[i].b], 1.0f);
    packSoftRows(rows, points, pointManifolds, bodies, s, packed);
    residuals.assign(std::size_t(s.substeps) * std::size_t(1 + s.relaxIterations), 0.0f);
    if (joints.empty()) {
        // Islands share no moving body: each one's substeps alone give the same bits, and a
        // small island's rows stay in the caches from one pass to the next.
        groupIslands(rows, pointManifolds, bodies, packed);
        const std::vector<std::uint32_t>& island = packed.order.islandStart;
        const auto part = [](const std::vector<std::uint32_t>& all,
                             const std::vector<std::uint32_t>& from, std::size_t j) {
            return std::span(all).subspan(from[j], from[j + 1] - from[j]);
        };
        for (std::size_t j = 0; j + 1 < island.size(); ++j) {
            const SoftGroup g{.begin = island[j],
                              .end = island[j + 1],
                              .landings = part(packed.islandLandings, packed.islandLandingStart, j),
                              .bodies = part(packed.islandBodies, packed.islandBodyStart, j),
                              .joints = {},
                              .jointSoftness = {}};
            runSubsteps(g, rows, points, pointManifolds, forcesShare, bodies, s, poses, packed,
                        residuals);
        }
        const SoftGroup rest{.begin = 0,
                             .end = 0,
                             .landings = {},
                             .bodies = packed.otherBodies,
                             .joints = {},
                             .jointSoftness = {}};
        runSubsteps(rest, rows, points, pointManifolds, forcesShare, bodies, s, poses, packed,
                    residuals);
    } else {
        std::vector<std::uint32_t> every(n);
        for (std::size_t i = 0; i < n; ++i) every[i] = std::uint32_t(i);
        const SoftGroup g{.begin = 0,
                          .end = rows.size(),
                          .landings = packed.landings,
                          .bodies = every,
                          .joints = joints,
                          .jointSoftness = jointSoftness};
        runSubsteps(g, rows, points, pointManifolds, forcesShare, bodies, s, poses, packed,
                    residuals);
    }
    unpackSoftRows(packed, rows, points);
    applyRestitution(rows, points, bodies, s.restitutionThreshold);
    // A landing's impulses stopped a hit, not a load: the next step starts its points cold, so
    // that its warm start does not throw the body back up and leave the point rows to take the
    // excess off unevenly.
    for (const SoftManifold& m : pointManifolds) {
        if (!isLanding(points, m, s.restitutionThreshold)) continue;
        for (std::uint32_t k = 0; k < m.count; ++k) {
            rows.normals[m.rows[k]].impulse = 0.0f;
            rows.frictions[m.rows[k]].impulse[0] = rows.frictions[m.rows[k]].impulse[1] = 0.0f;
        }
    }
}

} // namespace rubble
