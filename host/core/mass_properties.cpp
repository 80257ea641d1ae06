// host/core/mass_properties.cpp: closed forms for boxes and spheres, and polyhedral integration
// over triangles for hulls and meshes (Eberly 2002). Doubles throughout: thin or large meshes lose
// too much in float.
#include <numbers>
#include "host/core/mass_properties.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rubble {

MassProperties boxMassProperties(glm::vec3 halfExtents) {
    const glm::dvec3 h(halfExtents);
    MassProperties mp;
    mp.volume = 8.0 * h.x * h.y * h.z;
    // I = m/3 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2) for half extents a, b, c.
    const double k = mp.volume / 3.0;
    mp.inertia = glm::dmat3(0.0);
    mp.inertia[0][0] = k * (h.y * h.y + h.z * h.z);
    mp.inertia[1][1] = k * (h.x * h.x + h.z * h.z);
    mp.inertia[2][2] = k * (h.x * h.x + h.y * h.y);
    return mp;
}

MassProperties sphereMassProperties(float radius) {
    const double r = radius;
    MassProperties mp;
    mp.volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    mp.inertia = glm::dmat3(0.4 * mp.volume * r * r);
    return mp;
}

MassProperties capsuleMassProperties(float radius, float halfHeight) {
    const double r = radius, h = halfHeight, pi = std::numbers::pi;
    const double cylinder = pi * r * r * 2.0 * h;
    const double ball = 4.0 / 3.0 * pi * r * r * r; // the two hemispheres
    MassProperties mp;
    mp.volume = cylinder + ball;
    const double along = cylinder * r * r / 2.0 + ball * 2.0 / 5.0 * r * r;
    // Across: the cylinder's m (r^2/4 + L^2/12); the hemispheres' 83/320 m r^2 about their own
    // centres of mass plus m (h + 3r/8)^2, which sums to m (2r^2/5 + h^2 + 3hr/4).
    const double across = cylinder * (r * r / 4.0 + (2.0 * h) * (2.0 * h) / 12.0) +
                          ball * (83.0 / 320.0 * r * r + (h + 3.0 * r / 8.0) * (h + 3.0 * r / 8.0));
    mp.inertia = glm::dmat3(0.0);
    mp.inertia[0][0] = across;
    mp.inertia[1][1] = along;
    mp.inertia[2][2] = across;
    return mp;
}

namespace {

// The per-axis sums of one triangle's coordinates w0, w1, w2 that the face integrals need.
struct AxisSums {
    double f1, f2, f3, g0, g1, g2;
};

AxisSums axisSums(double w0, double w1, double w2) {
    const double t0 = w0 + w1;
    AxisSums s;
    s.f1 = t0 + w2;
    const double t1 = w0 * w0;
    const double t2 = t1 + w1 * t0;
    s.f2 = t2 + w2 * s.f1;
    s.f3 = w0 * t1 + w1 * t2 + w2 * s.f2;
    s.g0 = s.f2 + w0 * (s.f1 + w0);
    s.g1 = s.f2 + w1 * (s.f1 + w1);
    s.g2 = s.f2 + w2 * (s.f1 + w2);
    return s;
}

} // namespace

MassProperties polyhedronMassProperties(std::span<const glm::vec3> vertices,
                                        std::span<const glm::uvec3> triangles) {
    // Integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx over the solid.
    double in[10] = {};
    for (const glm::uvec3& t : triangles) {
        const glm::dvec3 p0(vertices[t.x]), p1(vertices[t.y]), p2(vertices[t.z]);
        // Unnormalised outward normal, twice the triangle's area.
        const glm::dvec3 d = glm::cross(p1 - p0, p2 - p0);
        const AxisSums sx = axisSums(p0.x, p1.x, p2.x);
        const AxisSums sy = axisSums(p0.y, p1.y, p2.y);
        const AxisSums sz = axisSums(p0.z, p1.z, p2.z);
        in[0] += d.x * sx.f1;
        in[1] += d.x * sx.f2;
        in[2] += d.y * sy.f2;
        in[3] += d.z * sz.f2;
        in[4] += d.x * sx.f3;
        in[5] += d.y * sy.f3;
        in[6] += d.z * sz.f3;
        in[7] += d.x * (p0.y * sx.g0 + p1.y * sx.g1 + p2.y * sx.g2);
        in[8] += d.y * (p0.z * sy.g0 + p1.z * sy.g1 + p2.z * sy.g2);
        in[9] += d.z * (p0.x * sz.g0 + p1.x * sz.g1 + p2.x * sz.g2);
    }
    const double scale[10] = {1.0 / 6,   1.0 / 24,  1.0 / 24,  1.0 / 24,  1.0 / 60,
                              1.0 / 60,  1.0 / 60,  1.0 / 120, 1.0 / 120, 1.0 / 120};
    for (int i = 0; i < 10; ++i) in[i] *= scale[i];

    MassProperties mp;
    mp.volume = in[0];
    if (mp.volume == 0.0) return mp;
    const glm::dvec3 c(in[1] / mp.volume, in[2] / mp.volume, in[3] / mp.volume);
    mp.centre = c;
    // Second moments about the origin, moved to the centre of mass (parallel axis theorem).
    const double m = mp.volume;
    const double xx = in[5] + in[6] - m * (c.y * c.y + c.z * c.z);
    const double yy = in[4] + in[6] - m * (c.z * c.z + c.x * c.x);
    const double zz = in[4] + in[5] - m * (c.x * c.x + c.y * c.y);
    const double xy = -(in[7] - m * c.x * c.y);
    const double yz = -(in[8] - m * c.y * c.z);
    const double zx = -(in[9] - m * c.z * c.x);
    mp.inertia = glm::dmat3(xx, xy, zx, xy, yy, yz, zx, yz, zz);
    return mp;
}

PrincipalAxes principalAxes(const glm::dmat3& inertia) {
    glm::dmat3 a = inertia;     // driven to diagonal
    glm::dmat3 v(1.0);          // accumulated rotations; a = v^T inertia v
    constexpr int kMaxSweeps = 32;
    for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
        const double off = a[1][0] * a[1][0] + a[2][0] * a[2][0] + a[2][1] * a[2][1];
        const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * diag) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                const double apq = a[q][p];
                if (apq == 0.0) continue;
                // The rotation in the (p, q) plane that zeroes a_pq.
                const double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
                const double t = (theta >= 0.0 ? 1.0 : -1.0) /
                                 (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                glm::dmat3 j(1.0);
                j[p][p] = c;
                j[q][q] = c;
                j[q][p] = s;  // row p, column q
                j[p][q] = -s; // row q, column p
                a = glm::transpose(j) * a * j;
                v = v * j;
            }
        }
    }
    if (glm::determinant(v) < 0.0) v[2] = -v[2]; // a rotation, not a reflection
    PrincipalAxes r;
    r.moments = glm::dvec3(a[0][0], a[1][1], a[2][2]);
    r.axes = glm::normalize(glm::quat_cast(v));
    return r;
}

glm::mat3 inertiaForMass(const MassProperties& mp, double mass) {
    return glm::mat3(mp.inertia * (mass / mp.volume));
}

Status checkMassRange(const shared::BodyMass& m, const std::string& where,
                      const std::string& field) {
    const float values[] = {m.mass,
                            m.inverseMass,
                            m.inertiaBody.r0.x,
                            m.inertiaBody.r1.y,
                            m.inertiaBody.r2.z,
                            m.inverseInertiaBody.r0.x,
                            m.inverseInertiaBody.r1.y,
                            m.inverseInertiaBody.r2.z};
    for (float v : values)
        if (!std::isnormal(v) || v < 0.0f) {
            char text[200];
            std::snprintf(text, sizeof text,
                          "its %s gives %g kg and a smallest moment of inertia of %g kg m^2 with "
                          "this shape: single precision cannot hold these and their inverses "
                          "(change the mass, density or size)",
                          field.c_str(), double(m.mass),
                          double(std::min({m.inertiaBody.r0.x, m.inertiaBody.r1.y,
                                           m.inertiaBody.r2.z})));
            return makeError(ErrorKind::BadInput, where, text);
        }
    return {};
}

} // namespace rubble
