// host/collision/particle_collision.h: CPU stages broadPhase and narrowPhase of the particle
// method, the twin of the device's: particles placed and gridded (broadPhase), then collided
// (narrowPhase), with host/collision/particles.h and host/collision/grid.h.
#pragma once

#include <vector>

#include "host/collision/collision_stage.h"
#include "host/collision/grid.h"
#include "host/collision/particles.h"

namespace rubble {

/// The particle collision method on the CPU.
class ParticleCollision final : public CollisionStage {
  public:
    explicit ParticleCollision(ContactForm form) : form_(form) {}

    /// Stages transformParticles and buildGrid. reads: poses, masses (flags)   writes: the
    /// particles' world positions, the grid
    Status broadPhase(const CollisionScene& scene, BodiesView bodies, const StepParams& params,
                      StepContacts& out) override;
    /// Stage collideParticles, contacts sorted by particle (as the device's deterministic mode
    /// has them). reads: the grid, masses   writes: points (or single-point manifolds when the
    /// solver reads manifolds), contactCount, largestPenetration
    Status narrowPhase(const CollisionScene& scene, BodiesView bodies,
                       const StepParams& params, StepContacts& out) override;
    /// The particle contacts as collided.
    void contactPoints(const StepContacts& contacts,
                       std::vector<shared::ParticleContact>& points) const override;
    /// Voxelises the bodies' shapes again (buildParticleSet). Errors: those of buildParticleSet.
    Status rebuild(const CollisionScene& scene, BodiesView bodies, float particleSpacing) override;

    const ParticleSet& set() const { return set_; }
    std::span<const shared::float4> world() const { return world_; }
    const ParticleGrid& grid() const { return grid_; }

  private:
    ContactForm form_;
    ParticleSet set_;
    std::vector<shared::float4> world_; ///< world positions (w = radius), per particle
    ParticleGrid grid_;
    std::vector<shared::ParticleContact> contacts_; ///< when the solver reads manifolds
};

} // namespace rubble
