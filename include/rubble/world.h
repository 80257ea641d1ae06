// include/rubble/world.h: a simulated world built from a Scene, stepped on the CPU reference
// pipeline or the OpenCL pipeline, with queries and forces for a host program.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/error.h"
#include "rubble/options.h"
#include "rubble/scene.h"

namespace rubble {

struct WorldState;

/// One body's state as a host program sees it; world frame, SI units.
struct BodyState {
    glm::vec3 position{0.0f};          ///< centre of mass, m
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f}; ///< body to world
    glm::vec3 linearVelocity{0.0f};    ///< m/s
    glm::vec3 angularVelocity{0.0f};   ///< rad/s
    glm::vec3 linearMomentum{0.0f};    ///< kg m/s
    glm::vec3 angularMomentum{0.0f};   ///< about the centre of mass, kg m^2/s
    float mass = 0.0f;                 ///< kg; 0 for static bodies
    bool isStatic = false;
    bool asleep = false;
};

/// Milliseconds spent in each stage of the last step (CPU wall time), and what it produced.
struct StepStats {
    double applyForcesMs = 0, integrateVelocitiesMs = 0, broadPhaseMs = 0, narrowPhaseMs = 0,
           buildContactRowsMs = 0, solveMs = 0, integratePositionsMs = 0, solvePositionsMs = 0,
           islandsMs = 0;
    double totalMs = 0;
    std::uint32_t pairCount = 0;    ///< broad-phase pairs
    std::uint32_t contactCount = 0; ///< contact points
    float largestPenetration = 0;   ///< m, before the solve
    float solverResidual = 0;       ///< largest |impulse change| in the last sweep, N s
};

/// A simulated world. Move-only.
class World {
  public:
    /// Builds the world of a scene: shapes (hulls, mass properties), bodies, joints, and the
    /// backend's resources. Errors: BadInput naming the scene field (degenerate hull, bad mass),
    /// NotSupported for a specified feature not built yet, Device for OpenCL failures.
    static Result<World> create(const Scene& scene, const RunOptions& run = {});

    World(World&&) noexcept;
    World& operator=(World&&) noexcept;
    ~World();

    /// Advances one step of options().dt. Errors: Numerical when a body's state becomes NaN or
    /// infinite (the message names the body and the step); stepping further is meaningless.
    Status step();

    /// Steps taken so far and the simulated time, s.
    std::int64_t stepIndex() const;
    double time() const;

    const SimulationOptions& options() const;
    const std::string& sceneName() const;

    /// Bodies are indexed 0..bodyCount()-1 in scene order.
    std::uint32_t bodyCount() const;
    const std::string& bodyName(std::uint32_t body) const;
    std::optional<std::uint32_t> findBody(std::string_view name) const;
    BodyState body(std::uint32_t body) const;

    /// Adds a force (N, world frame) at the centre of mass for the next step only.
    void addForce(std::uint32_t body, glm::vec3 force);
    /// Adds a torque (N m, world frame) for the next step only.
    void addTorque(std::uint32_t body, glm::vec3 torque);
    /// Adds a force (N) at a world point (m) for the next step only.
    void addForceAtPoint(std::uint32_t body, glm::vec3 force, glm::vec3 point);
    /// Applies an impulse (N s) at a world point (m) now, and wakes the body.
    void applyImpulse(std::uint32_t body, glm::vec3 impulse, glm::vec3 point);

    /// Statistics of the last step.
    const StepStats& lastStep() const;

    /// The OpenCL device's name, or "cpu".
    std::string deviceName() const;

    /// Internal arrays, for rubble's own stages and tests.
    WorldState& state();
    const WorldState& state() const;

  private:
    explicit World(std::unique_ptr<WorldState> s);
    std::unique_ptr<WorldState> s_;
};

} // namespace rubble
