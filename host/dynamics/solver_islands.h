// host/dynamics/solver_islands.h: the islands and sleep timers of a solver on manifolds (PGS,
// the soft step): the wake before the rows and each island's sleep after the step, over the
// bodies' bounding radii, read once.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/dynamics/contact_solver.h"
#include "host/dynamics/islands.h"

namespace rubble {

class SolverIslands {
  public:
    /// Islands touched by a restless body (on `approach`, the velocities before the forces)
    /// wake (wakeIslands): true when a body woke.
    bool wake(const SolverScene& scene, Bodies bodies,
              std::span<const shared::BodyVelocity> approach, std::span<const Manifold> manifolds);
    /// Each island's sleep on the step's velocities (updateSleep). Returns the bodies asleep.
    std::uint32_t sleep(const SolverScene& scene, Bodies bodies,
                        std::span<const Manifold> manifolds, float dt);
    /// The bodies were renumbered or removed: the timers and radii start again.
    void reset() {
        state_ = SleepState{};
        radii_.clear();
    }

  private:
    void prepareRadii(const SolverScene& scene, BodiesView bodies);
    SleepState state_;
    std::vector<float> radii_; ///< each body's bounding radius, m
};

} // namespace rubble
