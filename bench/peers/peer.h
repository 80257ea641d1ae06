// bench/peers/peer.h: the common front end of the peer engines' runners: the same scene file,
// the same steps and dt, timed per step, written in rubble's trajectory and metrics formats.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/geometry/shape.h"
#include "host/io/trajectory_writer.h"
#include "rubble/scene.h"

namespace CLI {
class App;
}

namespace rubble::peers {

/// One peer engine holding a scene's bodies, in scene order.
class PeerWorld {
  public:
    virtual ~PeerWorld() = default;
    /// Advances one step of the scene's dt.
    virtual void step() = 0;
    /// The state of every body in scene order (centre of mass, world frame).
    virtual void read(std::vector<TrajectoryRow>& rows) const = 0;
    /// Notes on what could not match rubble exactly, for the metrics file.
    virtual std::vector<std::string> caveats() const = 0;
    /// Dynamic bodies asleep now, for an engine that puts bodies to sleep (none: it does not).
    virtual std::optional<std::size_t> asleep() const { return std::nullopt; }
    /// What stepped it, for the metrics file's `device` (`box3d, 2 workers`); empty: the engine.
    virtual std::string device() const { return {}; }
    /// Adds a linear impulse (N s, world) at a dynamic body's centre of mass and wakes it, for the
    /// scene's explosions; false when the runner does not.
    virtual bool applyImpulse(std::size_t body, glm::vec3 impulse) {
        (void)body;
        (void)impulse;
        return false;
    }
};

/// Builds a peer world; shapes are rubble's built shapes (centre of mass at the origin).
using PeerFactory = std::function<Result<std::unique_ptr<PeerWorld>>(
    const Scene& scene, const std::vector<Shape>& shapes)>;

/// Adds a runner's own options to its command line (read before the factory is called).
using PeerOptions = std::function<void(CLI::App& app)>;

/// Parses `SCENE [--steps N] [--out FILE] [--every K] [--metrics FILE]` and the runner's own
/// options, runs the scene and writes the files; returns the process exit status (2 for bad
/// input).
int runPeer(int argc, char** argv, const std::string& engine, const std::string& version,
            const PeerFactory& factory, const PeerOptions& options = {});

/// The mass of a body as rubble computes it (mass, or density times the shape's volume).
double bodyMass(const BodyDesc& body, const Shape& shape);

} // namespace rubble::peers
