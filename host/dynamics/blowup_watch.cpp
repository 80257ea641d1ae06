// host/dynamics/blowup_watch.cpp: energy and joint watches after each step
// (host/dynamics/blowup_watch.h).
#include "host/dynamics/blowup_watch.h"

#include <algorithm>
#include <cstdio>

#include "host/core/math.h"

namespace rubble {
namespace {

bool isDynamic(const shared::BodyMass& m) { return m.inverseMass > 0.0f; }

// Kinetic plus potential energy of one body, J.
double bodyEnergy(const BlowUpInputs& in, std::size_t i) {
    const BodiesView& b = in.bodies;
    const glm::dvec3 v(toVec3(b.velocities[i].linear)), w(toVec3(b.velocities[i].angular));
    const glm::dvec3 p(toVec3(b.momenta[i].linear)), l(toVec3(b.momenta[i].angular));
    const glm::dvec3 x(toVec3(b.poses[i].position)), g(in.gravity);
    return 0.5 * (glm::dot(v, p) + glm::dot(w, l)) - double(b.masses[i].mass) * glm::dot(g, x);
}

float radiusOf(BodiesView bodies, std::span<const Shape> shapes, std::uint32_t i) {
    return shapes[bodies.shapeOf[i]].boundingRadius;
}

std::string joules(double j) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g J", j);
    return text;
}

// Starts the watch from the bodies as they are: their energies, and the allowance.
void rebase(BlowUpWatch& w, const BlowUpInputs& in) {
    const BodiesView& b = in.bodies;
    const std::size_t n = b.count();
    w.started = true;
    w.rebase = false;
    w.eventsFired = in.eventsFired;
    w.since = in.step;
    w.bodyAtLowest.assign(n, 0.0);
    const glm::dvec3 g(in.gravity);
    const double gravity = glm::length(g);
    const glm::dvec3 down = gravity > 0.0 ? g / gravity : glm::dvec3(0.0);
    double lo = 0.0, hi = 0.0, total = 0.0, kinetic = 0.0, weight = 0.0, own = 0.0, gain = 0.0;
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
        if (!isDynamic(b.masses[i])) continue;
        const double energy = bodyEnergy(in, i);
        const glm::dvec3 x(toVec3(b.poses[i].position));
        w.bodyAtLowest[i] = energy;
        total += energy;
        kinetic += energy + double(b.masses[i].mass) * glm::dot(g, x);
        const double m = b.masses[i].mass, r = radiusOf(b, in.shapes, std::uint32_t(i));
        const double depth = glm::dot(down, x);
        lo = any ? std::min(lo, depth) : depth;
        hi = any ? std::max(hi, depth) : depth;
        any = true;
        weight += m * gravity;
        const double push = 2.0 * double(in.baumgarte) * r / double(in.dt);
        own += m * gravity * 2.0 * r + 0.5 * m * push * push;
        gain += 0.5 * m * gravity * gravity * double(in.dt) * double(in.dt);
    }
    w.lowest = total;
    w.allowance = kKineticShare * std::max(kinetic, 0.0) + weight * (hi - lo) + own;
    w.explicitGain = in.explicitEuler ? gain : 0.0;
}

} // namespace

std::optional<BlowUp> watchEnergy(BlowUpWatch& w, const BlowUpInputs& in) {
    const std::size_t n = in.bodies.count();
    if (!w.started || w.rebase || in.eventsFired != w.eventsFired || w.bodyAtLowest.size() != n) {
        rebase(w, in);
        return std::nullopt;
    }
    w.bodyNow.resize(n);
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        w.bodyNow[i] = isDynamic(in.bodies.masses[i]) ? bodyEnergy(in, i) : 0.0;
        total += w.bodyNow[i];
    }
    if (total < w.lowest) {
        w.lowest = total;
        std::swap(w.bodyAtLowest, w.bodyNow);
        return std::nullopt;
    }
    const double allowed = w.allowance + w.explicitGain * double(in.step - w.since);
    if (total - w.lowest <= allowed) return std::nullopt;
    std::uint32_t worst = 0;
    double most = -1.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double gained = w.bodyNow[i] - w.bodyAtLowest[i];
        if (isDynamic(in.bodies.masses[i]) && gained > most) {
            most = gained;
            worst = std::uint32_t(i);
        }
    }
    BlowUp b;
    b.body = worst;
    b.message = "the simulation blew up in step " + std::to_string(in.step) +
                ": the bodies' energy (kinetic and potential) grew by " + joules(total - w.lowest) +
                " since step " + std::to_string(w.since) + ", more than the " + joules(allowed) +
                " the scene can account for; this body gained the most (" + joules(most) +
                "). A smaller dt, more solver iterations or smaller speeds may help";
    return b;
}

std::optional<BlowUp> watchJoints(std::span<const Joint> joints, BodiesView bodies,
                                  std::span<const Shape> shapes, std::int64_t step) {
    for (std::size_t k = 0; k < joints.size(); ++k) {
        const Joint& j = joints[k];
        float apart = 0.0f, turned = 0.0f;
        jointError(j, bodies.poses, apart, turned);
        const float span =
            kJointBreakRatio * (radiusOf(bodies, shapes, j.a) + radiusOf(bodies, shapes, j.b));
        if (!(apart > span)) continue;
        char text[200];
        std::snprintf(text, sizeof text,
                      "the simulation blew up in step %lld: joint %zu came apart, its anchors "
                      "%.4g m apart where its bodies together span %.4g m. A smaller dt or more "
                      "solver iterations may help",
                      static_cast<long long>(step), k, double(apart), double(span));
        return BlowUp{j.b, text};
    }
    return std::nullopt;
}

} // namespace rubble
