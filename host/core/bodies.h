// host/core/bodies.h: the body arrays as the stages see them, spans over a world's storage with
// one entry per body by index (hot: poses, velocities, momenta, forces; cold: masses, shapes,
// materials), and the storage itself. Stages take a view; only host/world owns the arrays.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rubble/shared/body.h"

namespace rubble {

/// The body arrays, read only.
struct BodiesView {
    std::span<const shared::BodyPose> poses;
    std::span<const shared::BodyVelocity> velocities; ///< derived from momenta and pose
    std::span<const shared::BodyMomentum> momenta;    ///< the state: P and L
    std::span<const shared::BodyForce> forces;        ///< this step's user forces
    std::span<const shared::BodyMass> masses;         ///< mass, inertia, flags
    std::span<const std::uint32_t> shapeOf;           ///< index into the world's shapes
    std::span<const std::uint32_t> materialOf;        ///< index into the world's materials

    std::uint32_t count() const { return std::uint32_t(poses.size()); }
    bool isStatic(std::uint32_t i) const { return masses[i].inverseMass == 0.0f; }
};

/// The body arrays as a stage that moves bodies sees them: the state and the flags (in masses)
/// may change; forces, shapes and materials may not.
struct Bodies {
    std::span<shared::BodyPose> poses;
    std::span<shared::BodyVelocity> velocities;
    std::span<shared::BodyMomentum> momenta;
    std::span<const shared::BodyForce> forces;
    std::span<shared::BodyMass> masses;
    std::span<const std::uint32_t> shapeOf;
    std::span<const std::uint32_t> materialOf;

    std::uint32_t count() const { return std::uint32_t(poses.size()); }
    bool isStatic(std::uint32_t i) const { return masses[i].inverseMass == 0.0f; }
    operator BodiesView() const {
        return {poses, velocities, momenta, forces, masses, shapeOf, materialOf};
    }
};

/// The storage of the body arrays: sized together, at load and when bodies are added or removed.
struct BodyArrays {
    std::vector<shared::BodyPose> poses;
    std::vector<shared::BodyVelocity> velocities;
    std::vector<shared::BodyMomentum> momenta;
    std::vector<shared::BodyForce> forces;
    std::vector<shared::BodyMass> masses;
    std::vector<std::uint32_t> shapeOf;
    std::vector<std::uint32_t> materialOf;

    std::uint32_t count() const { return std::uint32_t(poses.size()); }
    bool isStatic(std::uint32_t i) const { return masses[i].inverseMass == 0.0f; }
    Bodies view() { return {poses, velocities, momenta, forces, masses, shapeOf, materialOf}; }
    BodiesView view() const {
        return {poses, velocities, momenta, forces, masses, shapeOf, materialOf};
    }
};

} // namespace rubble
