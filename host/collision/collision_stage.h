// host/collision/collision_stage.h: the two collision stages of the CPU step (broadPhase,
// narrowPhase) behind one interface, so that a world picks its collision method once, when it is
// built: SatCollision (host/collision/sat_collision.h, the reference) or ParticleCollision
// (host/collision/particle_collision.h, the twin of the device's).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "host/collision/contact.h"
#include "host/core/bodies.h"
#include "host/core/step_params.h"
#include "host/geometry/shape.h"
#include "rubble/error.h"
#include "rubble/shared/particle.h"

namespace rubble {

/// The form of contacts a solver reads: manifolds (PGS) or contact points (the jacobi family).
enum class ContactForm { Manifolds, Points };

/// What the collision stages read of the world besides the body arrays. It changes only when
/// bodies are added or removed, after which the world calls CollisionStage::rebuild.
struct CollisionScene {
    std::span<const Shape> shapes;
    std::span<const MaterialDesc> materials;
    std::span<const BodyPair> joined; ///< joined bodies, (min, max), sorted: they do not collide
};

/// One step's contacts: the broad phase's pairs, then the narrow phase's contacts in the form
/// the solver reads, and what the step reports of them.
struct StepContacts {
    std::vector<BodyPair> pairs;                 ///< sorted, a < b
    std::vector<Manifold> manifolds;             ///< ContactForm::Manifolds, in pair order
    std::vector<shared::ParticleContact> points; ///< ContactForm::Points
    std::uint32_t contactCount = 0;              ///< contact points
    float largestPenetration = 0.0f;             ///< m
};

/// A collision method's stages, with what they keep between steps.
class CollisionStage {
  public:
    virtual ~CollisionStage() = default;

    /// Stage broadPhase. reads: bodies, scene, params   writes: out.pairs, the stage's cache.
    /// Errors: Limit naming the stage when the pairs pass their budget (host/core/limits.h); the
    /// pairs are then left empty.
    [[nodiscard]] virtual Status broadPhase(const CollisionScene& scene, BodiesView bodies,
                                            const StepParams& params, StepContacts& out) = 0;
    /// Stage narrowPhase. reads: bodies, scene, params, out.pairs   writes: out's contacts in the
    /// form the stage was made for, contactCount, largestPenetration, the stage's cache.
    /// Errors: Limit naming the stage when the contacts pass their budget (host/core/limits.h).
    [[nodiscard]] virtual Status narrowPhase(const CollisionScene& scene, BodiesView bodies,
                                             const StepParams& params, StepContacts& out) = 0;
    /// The step's contacts as points, whatever form they were delivered in (the contact set of
    /// `rubble solvers`). reads: out of the last narrowPhase   writes: points
    virtual void contactPoints(const StepContacts& contacts,
                               std::vector<shared::ParticleContact>& points) const = 0;
    /// At load and after bodies were added or removed: what the stage derives from the bodies
    /// is made again and what it keeps by body index is forgotten. Errors: BadInput or
    /// NotSupported naming the option or the bodies that the method cannot take.
    [[nodiscard]] virtual Status rebuild(const CollisionScene& scene, BodiesView bodies,
                                         float particleSpacing) = 0;
};

/// The stage object of a collision method, delivering contacts in the given form.
std::unique_ptr<CollisionStage> makeCollisionStage(CollisionMethod method, ContactForm form);

} // namespace rubble
