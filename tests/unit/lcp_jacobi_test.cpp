// tests/unit/lcp_jacobi_test.cpp: the dense contact problem (A = J M^-1 J^T against an explicit
// Jacobian), the projection, the iterative solvers approaching Lemke's answer on a frozen stack,
// and the lcp-jacobi and lemke solvers stepping worlds.
#include <random>

#include <gtest/gtest.h>

#include "host/core/math.h"
#include "host/dynamics/lcp_convergence.h"
#include "host/dynamics/lcp_jacobi.h"
#include "host/world/frozen_contacts.h"
#include "support/test_util.h"

namespace rubble {
namespace {

using namespace shared;

// Four bodies (body 0 static) with random masses, inertias and poses, and contacts between
// random pairs.
struct RandomContacts {
    std::vector<BodyPose> poses;
    std::vector<BodyVelocity> velocities;
    std::vector<BodyMass> masses;
    std::vector<shared::ContactRow> rows;
};

RandomContacts randomContacts(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), pos(0.5f, 2.0f);
    RandomContacts r;
    const int bodies = 4;
    for (int i = 0; i < bodies; ++i) {
        const glm::quat q = glm::normalize(glm::quat(u(rng), u(rng), u(rng), u(rng)));
        r.poses.push_back(BodyPose{toFloat4(glm::vec3(u(rng), u(rng), u(rng))), toFloat4(q)});
        r.velocities.push_back(BodyVelocity{toFloat4(glm::vec3(u(rng), u(rng), u(rng))),
                                            toFloat4(glm::vec3(u(rng), u(rng), u(rng)))});
        BodyMass m{};
        if (i > 0) {
            m.mass = pos(rng);
            m.inverseMass = 1.0f / m.mass;
            const glm::mat3 inertia(glm::vec3(pos(rng), 0, 0), glm::vec3(0, pos(rng), 0),
                                    glm::vec3(0, 0, pos(rng)));
            m.inertiaBody = toShared(inertia);
            m.inverseInertiaBody = toShared(glm::inverse(inertia));
        }
        r.masses.push_back(m);
    }
    for (int c = 0; c < 7; ++c) {
        shared::ContactRow row{};
        row.a = std::uint32_t(c % bodies);
        row.b = std::uint32_t((c % bodies + 1 + c % 3) % bodies);
        if (row.a == row.b) row.b = (row.b + 1) % bodies;
        row.normal = normalize3(vec4(u(rng), u(rng), u(rng)));
        row.tangent1 = perpendicularItem(row.normal);
        row.tangent2 = cross3(row.normal, row.tangent1);
        row.rA = vec4(u(rng), u(rng), u(rng));
        row.rB = vec4(u(rng), u(rng), u(rng));
        row.bias = -0.1f * pos(rng);
        row.friction = 0.5f;
        row.lambda = vec4(0.3f, -0.1f, 0.05f);
        r.rows.push_back(row);
    }
    return r;
}

TEST(DenseLcp, TheDelassusMatrixIsJMInverseJTransposed) {
    const RandomContacts r = randomContacts(3);
    DenseLcp p;
    buildLcpRows(r.rows, r.velocities, r.masses, r.poses, 3u, p);
    assembleDelassus(p);
    const std::size_t m = p.size(), cols = 6 * r.poses.size();
    ASSERT_EQ(m, 21u);
    // The explicit Jacobian (rows x 6 bodies) and M^-1 (block diagonal), in double.
    std::vector<double> j(m * cols, 0.0), minv(cols * cols, 0.0);
    for (std::size_t b = 0; b < r.poses.size(); ++b) {
        const glm::mat3 ii = toMat3(inverseInertiaWorldItem(r.masses[b], r.poses[b].orientation));
        for (int k = 0; k < 3; ++k) {
            minv[(6 * b + k) * cols + 6 * b + k] = r.masses[b].inverseMass;
            for (int l = 0; l < 3; ++l) minv[(6 * b + 3 + k) * cols + 6 * b + 3 + l] = ii[l][k];
        }
    }
    std::vector<double> v(cols);
    for (std::size_t b = 0; b < r.poses.size(); ++b) {
        const glm::vec3 lin = toVec3(r.velocities[b].linear), ang = toVec3(r.velocities[b].angular);
        for (int k = 0; k < 3; ++k) {
            v[6 * b + k] = lin[k];
            v[6 * b + 3 + k] = ang[k];
        }
    }
    for (std::size_t c = 0; c < r.rows.size(); ++c)
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::size_t i = c * 3 + k;
            const glm::vec3 d = toVec3(rowDirectionItem(r.rows[c], k));
            const glm::vec3 ca = glm::cross(toVec3(r.rows[c].rA), d);
            const glm::vec3 cb = glm::cross(toVec3(r.rows[c].rB), d);
            for (int e = 0; e < 3; ++e) {
                j[i * cols + 6 * r.rows[c].a + e] -= d[e];
                j[i * cols + 6 * r.rows[c].a + 3 + e] -= ca[e];
                j[i * cols + 6 * r.rows[c].b + e] += d[e];
                j[i * cols + 6 * r.rows[c].b + 3 + e] += cb[e];
            }
        }
    for (std::size_t i = 0; i < m; ++i) {
        double jv = 0.0;
        for (std::size_t k = 0; k < cols; ++k) jv += j[i * cols + k] * v[k];
        const double expectedB = jv + (i % 3 == 0 ? r.rows[i / 3].bias : 0.0f);
        EXPECT_NEAR(p.rhs[i], expectedB, 1e-5 * (1.0 + std::abs(expectedB))) << "b[" << i << "]";
        for (std::size_t l = 0; l < m; ++l) {
            double a = 0.0;
            for (std::size_t x = 0; x < cols; ++x)
                for (std::size_t y = 0; y < cols; ++y)
                    a += j[i * cols + x] * minv[x * cols + y] * j[l * cols + y];
            EXPECT_NEAR(p.matrix[i * m + l], a, 1e-5 * (1.0 + std::abs(a))) << i << ", " << l;
        }
    }
    // The warm-start impulses become lambda; friction per contact.
    EXPECT_EQ(p.lambda[0], 0.3f);
    EXPECT_EQ(p.lambda[1], -0.1f);
    EXPECT_EQ(p.friction[0], 0.5f);
}

TEST(DenseLcp, RowScalesAreTheRowSumsOfAbsoluteEntries) {
    const RandomContacts r = randomContacts(4);
    DenseLcp p;
    buildLcpRows(r.rows, r.velocities, r.masses, r.poses, 1u, p);
    assembleDelassus(p);
    scaleLcpRows(p);
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
        float sum = 0.0f;
        for (std::size_t j = 0; j < n; ++j) sum += std::fabs(p.matrix[i * n + j]);
        EXPECT_FLOAT_EQ(p.inverseScale[i], 1.0f / sum);
    }
}

TEST(DenseLcp, TheProjectionKeepsNormalsPositiveAndFrictionInItsBox) {
    const float4 lambda = vec4(0.2f, 0.1f, -0.1f), scale = vec4(1.0f, 1.0f, 1.0f);
    // Pulling apart: the normal impulse drops to 0 and friction with it.
    const float4 apart = projectLcpItem(lambda, vec4(5.0f, 0.0f, 0.0f), scale, 0.5f, 1.0f, 3u);
    EXPECT_EQ(apart.x, 0.0f);
    EXPECT_EQ(apart.y, 0.0f);
    EXPECT_EQ(apart.z, 0.0f);
    // Pressing: friction clamped to mu times the new normal impulse.
    const float4 pressed = projectLcpItem(lambda, vec4(-1.0f, -3.0f, 3.0f), scale, 0.5f, 1.0f, 3u);
    EXPECT_FLOAT_EQ(pressed.x, 1.2f);
    EXPECT_FLOAT_EQ(pressed.y, 0.6f);
    EXPECT_FLOAT_EQ(pressed.z, -0.6f);
    // One row per contact: the tangents stay 0.
    const float4 normalOnly = projectLcpItem(lambda, vec4(-1.0f, -3.0f, 3.0f), scale, 0.5f, 1.0f, 1u);
    EXPECT_EQ(normalOnly.y, 0.0f);
}

std::string stack(int boxes, float friction) {
    std::string bodies = R"({"name": "floor", "shape": "floor", "static": true})";
    for (int i = 0; i < boxes; ++i)
        bodies += R"(, {"name": "box)" + std::to_string(i) + R"(", "shape": "crate", "mass": 1,
                       "position": [0, )" + std::to_string(0.5 + i) + ", 0]}";
    return R"({"format": "rubble-scene", "version": 1, "name": "stack",
      "simulation": {"dt": 0.016666667, "solver": {"type": "pgs", "iterations": 10}},
      "materials": {"default": {"friction": )" + std::to_string(friction) + R"(}},
      "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0},
                 "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
      "bodies": [)" + bodies + "]}";
}

double velocityError(const FrozenProblem& p, const Iterates& it, int k,
                     const LemkeSolution& exact) {
    return *measureIterate(p.dense, it[std::size_t(k - 1)], exact.w).velocityError;
}

// A frictionless stack of three boxes at step 30 (four SAT points per face): Lemke solves it
// exactly; pgs, jacobi and lcp-jacobi approach its contact velocities as iterations grow and
// are within 1e-5 m/s of them after 1000.
TEST(FrozenStack, TheIterativeSolversApproachLemke) {
    World w = test::worldFromText(stack(3, 0.0f));
    Result<FrozenContacts> set = freezeContacts(w, 30);
    ASSERT_TRUE(set.ok()) << set.error().describe();
    ASSERT_EQ(set->contacts.size(), 12u);
    Result<FrozenProblem> p = freezeProblem(*set);
    ASSERT_TRUE(p.ok());
    ASSERT_EQ(p->dense.stride, 1u);
    Result<LemkeSolution> exact = lemkeOf(*p);
    ASSERT_TRUE(exact.ok()) << exact.error().describe();
    EXPECT_LT(measureIterate(p->dense, std::span<const double>(exact->z)).residual, 1e-9);
    const SolverOptions& o = p->set.solver;
    const std::pair<const char*, Iterates> solvers[] = {
        {"pgs", pgsIterates(*p, 1000, o.relaxation)},
        {"jacobi", jacobiIterates(*p, 1000, jacobiRelaxation(o))},
        {"lcp-jacobi", lcpJacobiIterates(*p, 1000, lcpJacobiRelaxation(o))}};
    for (const auto& [name, it] : solvers) {
        SCOPED_TRACE(name);
        const double e10 = velocityError(*p, it, 10, *exact), e100 = velocityError(*p, it, 100, *exact),
                     e1000 = velocityError(*p, it, 1000, *exact);
        EXPECT_GT(e10, e100);
        EXPECT_GE(e100, e1000);
        EXPECT_LT(e1000, 1e-5);
        EXPECT_LT(measureIterate(p->dense, it.back()).residual, 1e-5);
    }
}

TEST(FrozenStack, LemkeIsRefusedOnAContactSetWithFriction) {
    World w = test::worldFromText(stack(2, 0.5f));
    Result<FrozenContacts> set = freezeContacts(w, 10);
    ASSERT_TRUE(set.ok());
    Result<FrozenProblem> p = freezeProblem(*set);
    ASSERT_TRUE(p.ok());
    EXPECT_EQ(p->dense.stride, 3u);
    Result<LemkeSolution> exact = lemkeOf(*p);
    ASSERT_FALSE(exact.ok());
    EXPECT_EQ(exact.error().kind, ErrorKind::NotSupported);
}

TEST(FrozenStack, StepZeroIsBadInput) {
    World w = test::worldFromText(stack(1, 0.0f));
    Result<FrozenContacts> set = freezeContacts(w, 0);
    ASSERT_FALSE(set.ok());
    EXPECT_EQ(set.error().kind, ErrorKind::BadInput);
}

std::string withSolver(std::string json, const std::string& solver) {
    const std::string from = R"("type": "pgs")";
    json.replace(json.find(from), from.size(), R"("type": ")" + solver + "\"");
    return json;
}

// Lemke's exact impulses hold a frictionless stack of three still: after 2 s every box is
// within 1 mm of where it started.
TEST(DenseSolvers, LemkeHoldsAFrictionlessStackStill) {
    World w = test::worldFromText(withSolver(stack(3, 0.0f), "lemke"));
    for (int i = 0; i < 120; ++i) ASSERT_TRUE(w.step().ok()) << "step " << i;
    for (std::uint32_t b = 1; b < w.bodyCount(); ++b) {
        EXPECT_NEAR(w.body(b).position.y, 0.5f + float(b - 1), 1e-3f) << w.bodyName(b);
        EXPECT_LT(glm::length(w.body(b).linearVelocity), 1e-3f) << w.bodyName(b);
    }
}

// lcp-jacobi with friction on SAT and on particles: a stack of three stands for 2 s.
TEST(DenseSolvers, LcpJacobiHoldsAStackUp) {
    for (const char* collision : {"sat", "particles"}) {
        SCOPED_TRACE(collision);
        std::string json = withSolver(stack(3, 0.5f), "lcp-jacobi");
        json.replace(json.find(R"("solver")"), 8,
                     R"("collision": {"method": ")" + std::string(collision) +
                         R"(", "particle_spacing": 0.25}, "solver")");
        World w = test::worldFromText(json);
        for (int i = 0; i < 120; ++i) ASSERT_TRUE(w.step().ok()) << "step " << i;
        const BodyState top = w.body(3);
        EXPECT_NEAR(top.position.y, 2.5f, 0.05f);
        EXPECT_NEAR(top.position.x, 0.0f, 0.02f);
        EXPECT_LT(glm::length(top.linearVelocity), 0.05f);
    }
}

TEST(DenseSolvers, LemkeWithFrictionIsRefusedNamingTheMaterial) {
    const Error e = test::sceneError(withSolver(stack(2, 0.5f), "lemke"));
    EXPECT_EQ(e.kind, ErrorKind::NotSupported);
    EXPECT_EQ(e.where, "inline.json: materials.default.friction");
    EXPECT_NE(e.message.find("frictionless"), std::string::npos) << e.message;
}

// Particles 0.1 m apart put about a hundred contacts under each box: seven boxes exceed what
// Lemke's method takes, and the step says so.
TEST(DenseSolvers, LemkeRefusesMoreThan600Rows) {
    std::string json = withSolver(stack(1, 0.0f), "lemke");
    json.replace(json.find(R"("solver")"), 8,
                 R"("collision": {"method": "particles", "particle_spacing": 0.1}, "solver")");
    std::string boxes;
    for (int i = 0; i < 7; ++i)
        boxes += R"(, {"name": "flat)" + std::to_string(i) + R"(", "shape": "crate", "mass": 1,
                     "position": [)" + std::to_string(2.0 * (i + 1)) + ", 0.49, 0]}";
    json.insert(json.rfind(']'), boxes);
    World w = test::worldFromText(json);
    Status failed;
    for (int i = 0; i < 5 && failed.ok(); ++i) failed = w.step();
    ASSERT_FALSE(failed.ok());
    EXPECT_EQ(failed.error().kind, ErrorKind::NotSupported);
    EXPECT_NE(failed.error().message.find("at most 600"), std::string::npos)
        << failed.error().describe();
}

} // namespace
} // namespace rubble
