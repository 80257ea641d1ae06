// host/collision/particles.cpp: OpenCL stages transformParticles and collideParticles on the
// CPU; twins of kernels/particles.cl.
#include "host/collision/particles.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "host/core/assert.h"
#include "host/core/limits.h"
#include "host/core/math.h"
#include "host/geometry/voxelise.h"

namespace rubble {

using namespace shared;

namespace {

// Refuses a spacing that would voxelise a shape into more cells or ray tests than a world may
// spend on it, before any is allocated.
Status checkVoxelCost(const Shape& shape, float spacing) {
    const VoxelCost cost = voxelCost(shape, spacing);
    if (cost.cells <= kMaxVoxels && cost.rayTests <= kMaxVoxelWork) return {};
    char text[256];
    std::snprintf(text, sizeof text,
                  "of %g m voxelises shape %s into %.3g cells (%.3g ray tests), more than the "
                  "%.3g cells and %.3g tests a shape may take (docs/scene-format.md, Limits); "
                  "use a larger spacing",
                  double(spacing), shape.name.c_str(), cost.cells, cost.rayTests, kMaxVoxels,
                  kMaxVoxelWork);
    return makeError(ErrorKind::Limit, "simulation.collision.particle_spacing", text);
}

// A shape's voxels in a fixed scattered order instead of the voxeliser's rows. Gauss-Seidel
// sweeps a pair's particle contacts in particle order; in rows, every sweep met the same corner
// of a face first and turned the crate the same way (a stack of 8-particle crates swayed, 0.26 m
// at the top, and pyramid_20 fell on the CPU). The order is that of the index times Knuth's
// multiplicative constant, the same on every run.
std::vector<glm::vec3> scatteredOrder(const std::vector<glm::vec3>& cells) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> keys;
    keys.reserve(cells.size());
    for (std::uint32_t i = 0; i < cells.size(); ++i) keys.push_back({i * 2654435761u, i});
    std::sort(keys.begin(), keys.end());
    std::vector<glm::vec3> out;
    out.reserve(cells.size());
    for (const auto& k : keys) out.push_back(cells[k.second]);
    return out;
}

} // namespace

Result<ParticleSet> buildParticleSet(std::span<const Shape> shapes,
                                     std::span<const MaterialDesc> materials, BodiesView bodies,
                                     float spacing, bool pgs) {
    // The Jacobi solvers' rows push apart only what overlaps: no speculative gap for them.
    const float margin = pgs ? kParticleContactMargin : 0.0f;
    ParticleSet p;
    std::map<std::uint32_t, std::vector<glm::vec3>> byShape;
    for (std::uint32_t b = 0; b < bodies.count(); ++b) {
        const Shape& shape = shapes[bodies.shapeOf[b]];
        const MaterialDesc& material = materials[bodies.materialOf[b]];
        const bool fixed = bodies.isStatic(b);
        if (shape.type == ShapeType::Plane || (fixed && shape.type == ShapeType::Box)) {
            StaticShape st{};
            st.kind = shape.type == ShapeType::Plane ? RUBBLE_STATIC_PLANE : RUBBLE_STATIC_BOX;
            // A static body's pose turns its shape: the plane's normal and offset follow it.
            const glm::quat q = toQuat(bodies.poses[b].orientation);
            const glm::vec3 x = toVec3(bodies.poses[b].position);
            const glm::vec3 n = glm::normalize(q * shape.normal);
            st.normal = toFloat4(n, shape.offset + glm::dot(n, x));
            st.position = bodies.poses[b].position;
            st.orientation = bodies.poses[b].orientation;
            st.halfExtents = toFloat4(shape.halfExtents);
            st.friction = material.friction;
            st.restitution = material.restitution;
            st.body = b;
            p.statics.push_back(st);
            continue;
        }
        auto it = byShape.find(bodies.shapeOf[b]);
        if (it == byShape.end()) {
            RUBBLE_TRY(checkVoxelCost(shape, spacing));
            std::vector<glm::vec3> cells = voxeliseShape(shape, spacing, true);
            if (pgs) cells = scatteredOrder(cells);
            it = byShape.emplace(bodies.shapeOf[b], std::move(cells)).first;
        }
        if (p.particles.size() + it->second.size() > kMaxParticles)
            return makeError(ErrorKind::Limit, "simulation.collision.particle_spacing",
                             "gives more than " + std::to_string(kMaxParticles) +
                                 " particles to the first " + std::to_string(b + 1) +
                                 " bodies, more than a world may have (docs/scene-format.md, "
                                 "Limits); use a larger spacing");
        for (const glm::vec3& c : it->second) {
            Particle particle{};
            particle.offset = toFloat4(c, 0.5f * spacing);
            particle.body = b;
            p.particles.push_back(particle);
        }
    }
    if (p.particles.size() >= std::size_t(0x7fffffff))
        return makeError(ErrorKind::BadInput, "simulation.collision.particle_spacing",
                         "gives " + std::to_string(p.particles.size()) +
                             " particles, more than the pipeline can index; use a larger spacing");
    if (p.statics.size() > RUBBLE_MAX_STATIC_SHAPES)
        return makeError(
            ErrorKind::NotSupported, "bodies",
            "the particle method meets at most " + std::to_string(RUBBLE_MAX_STATIC_SHAPES) +
                " planes and static boxes; this scene has " + std::to_string(p.statics.size()));
    // A cell at least as wide as the farthest contact: the 27 neighbours hold every one.
    p.cellSize = spacing + margin;
    p.margin = margin;
    p.bits = gridBits(p.particles.size());
    return p;
}

void transformParticles(std::span<const Particle> particles, std::span<const BodyPose> poses,
                        std::span<float4> world) {
    RUBBLE_ASSERT(world.size() == particles.size());
    for (std::size_t i = 0; i < particles.size(); ++i)
        world[i] = transformParticleItem(particles[i], poses[particles[i].body]);
}

void transformParticles(std::span<const Particle> particles, std::span<const BodyPose> poses,
                        std::span<const BodyMass> masses, std::span<float4> world) {
    RUBBLE_ASSERT(world.size() == particles.size());
    for (std::size_t i = 0; i < particles.size(); ++i) {
        // Sleeping bodies do not move: their particles keep their positions.
        if (masses[particles[i].body].flags & RUBBLE_BODY_ASLEEP) continue;
        world[i] = transformParticleItem(particles[i], poses[particles[i].body]);
    }
}

bool collideParticles(const ParticleSet& set, std::span<const float4> world,
                      const ParticleGrid& grid, std::span<const BodyMass> masses,
                      std::vector<ParticleContact>& contacts, std::size_t maxContacts) {
    contacts.clear();
    const float inverse = 1.0f / set.cellSize;
    const std::uint32_t count = std::uint32_t(set.particles.size());
    for (std::uint32_t slot = 0; slot < count; ++slot) {
        const std::uint32_t i = grid.order[slot];
        const float4 xi = world[i];
        const std::uint32_t bodyI = set.particles[i].body;
        const std::uint32_t flagsI = masses[bodyI].flags;
        if (!testsPairsItem(flagsI)) continue;
        const int cx = cellCoordinate(xi.x, inverse), cy = cellCoordinate(xi.y, inverse),
                  cz = cellCoordinate(xi.z, inverse);
        std::uint32_t seen[27];
        std::uint32_t seenCount = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::uint32_t key = cellHashItem(cx + dx, cy + dy, cz + dz, set.bits);
                    RUBBLE_ASSERT(neighbourCellIsNewItem(seen, seenCount, key));
                    seen[seenCount++] = key;
                    const std::uint32_t start = grid.cellStart[key];
                    if (start == RUBBLE_EMPTY_CELL) continue;
                    for (std::uint32_t s = start; s < grid.cellEnd[key]; ++s) {
                        const std::uint32_t j = grid.order[s];
                        if (!particlesMayTouchItem(xi, world[j], set.margin)) continue;
                        const std::uint32_t bodyJ = set.particles[j].body;
                        const std::uint32_t flagsJ = masses[bodyJ].flags;
                        if (!pairFromHereItem(bodyI, flagsI, bodyJ, flagsJ, s > slot)) continue;
                        // Two active bodies meet in the order of their indices.
                        const bool swap = activeBodyItem(flagsJ) && bodyJ < bodyI;
                        ParticleContact c =
                            swap ? particlePairItem(world[j], xi) : particlePairItem(xi, world[j]);
                        if (!particleContactMadeItem(c.point.w, set.margin)) continue;
                        c.a = swap ? bodyJ : bodyI;
                        c.b = swap ? bodyI : bodyJ;
                        c.particleA = swap ? j : i;
                        c.featureB = swap ? i : j;
                        contacts.push_back(c);
                        if (contacts.size() > maxContacts) return false;
                    }
                }
        if (!activeBodyItem(flagsI)) continue;
        for (std::uint32_t k = 0; k < set.statics.size(); ++k) {
            ParticleContact c = particleStaticItem(xi, set.statics[k]);
            if (!particleContactMadeItem(c.point.w, set.margin)) continue;
            c.a = bodyI;
            c.particleA = i;
            c.featureB = count + k;
            contacts.push_back(c);
            if (contacts.size() > maxContacts) return false;
        }
    }
    return true;
}

void sortContactsByParticle(std::vector<ParticleContact>& contacts) {
    std::sort(
        contacts.begin(), contacts.end(), [](const ParticleContact& x, const ParticleContact& y) {
            return x.particleA != y.particleA ? x.particleA < y.particleA : x.featureB < y.featureB;
        });
}

void particleContactsToManifolds(std::span<const ParticleContact> contacts,
                                 std::vector<Manifold>& manifolds) {
    manifolds.clear();
    manifolds.reserve(contacts.size());
    for (const ParticleContact& c : contacts) {
        Manifold m;
        const bool swap = c.a > c.b;
        m.a = swap ? c.b : c.a;
        m.b = swap ? c.a : c.b;
        m.normal = toVec3(c.normal) * (swap ? -1.0f : 1.0f);
        m.count = 1;
        m.points[0].position = toVec3(c.point);
        m.points[0].depth = c.point.w;
        m.points[0].normal = m.normal;
        m.points[0].feature = shared::particleFeatureItem(c.particleA, c.featureB);
        manifolds.push_back(m);
    }
    // The reference solver expects manifolds grouped by pair.
    std::stable_sort(manifolds.begin(), manifolds.end(), [](const Manifold& x, const Manifold& y) {
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
}

} // namespace rubble
