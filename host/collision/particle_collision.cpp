// host/collision/particle_collision.cpp: the particle method's CPU stages over the body arrays,
// and the choice of a collision method's stage object.
#include "host/collision/particle_collision.h"

#include <algorithm>

#include "host/collision/sat_collision.h"
#include "host/core/limits.h"

namespace rubble {

Status ParticleCollision::broadPhase(const CollisionScene&, BodiesView bodies, const StepParams&,
                                     StepContacts&) {
    transformParticles(set_.particles, bodies.poses, bodies.masses, world_);
    buildGrid(world_, set_.cellSize, set_.bits, grid_);
    return {};
}

Status ParticleCollision::narrowPhase(const CollisionScene&, BodiesView bodies,
                                      const StepParams& params, StepContacts& out) {
    std::vector<shared::ParticleContact>& contacts =
        form_ == ContactForm::Points ? out.points : contacts_;
    const std::size_t budget = particleContactBudget(set_.particles.size());
    if (!collideParticles(set_, world_, grid_, bodies.masses, contacts, budget)) {
        const std::size_t found = contacts.size();
        contacts.clear();
        out.manifolds.clear();
        out.contactCount = 0;
        return limitError("collideParticles", "particle contacts", found, budget, params.step + 1,
                          "bodies overlap each other in large numbers");
    }
    sortContactsByParticle(contacts);
    float deepest = 0.0f;
    for (const shared::ParticleContact& c : contacts) deepest = std::max(deepest, c.point.w);
    out.contactCount = std::uint32_t(contacts.size());
    out.largestPenetration = deepest;
    if (form_ == ContactForm::Manifolds) particleContactsToManifolds(contacts, out.manifolds);
    return {};
}

void ParticleCollision::contactPoints(const StepContacts& contacts,
                                      std::vector<shared::ParticleContact>& points) const {
    points = form_ == ContactForm::Points ? contacts.points : contacts_;
}

Status ParticleCollision::rebuild(const CollisionScene& scene, BodiesView bodies,
                                  float particleSpacing) {
    Result<ParticleSet> set = buildParticleSet(scene.shapes, scene.materials, bodies,
                                               particleSpacing, form_ == ContactForm::Manifolds);
    RUBBLE_TRY(set);
    set_ = std::move(*set);
    world_.assign(set_.particles.size(), shared::float4{});
    return {};
}

std::unique_ptr<CollisionStage> makeCollisionStage(CollisionMethod method, ContactForm form) {
    if (method == CollisionMethod::Particles) return std::make_unique<ParticleCollision>(form);
    return std::make_unique<SatCollision>(form);
}

} // namespace rubble
