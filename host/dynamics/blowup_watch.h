// host/dynamics/blowup_watch.h: after every step, whether the simulation blew up: the bodies'
// mechanical energy grew by more than the scene can account for, or a joint came apart. A
// blow-up is the run's failure (ErrorKind::Numerical, exit status 3), never a silent exit 0: a
// step far too long for the scene's forces throws bodies away, a body spun far too fast gains
// energy without bound, a driven hinge leaves its body far from its pin.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/core/bodies.h"
#include "host/dynamics/joints.h"
#include "host/geometry/shape.h"

namespace rubble {

/// A joint is broken when its anchors are further apart than this many times the sum of its
/// bodies' bounding radii.
inline constexpr float kJointBreakRatio = 1.0f;

/// The share of the kinetic energy at the reference that the total may gain: rounding and the
/// solvers' own small gains (a torque-free body tumbling at 6 rad/s keeps its energy to 1e-3).
inline constexpr double kKineticShare = 0.1;

/// What the energy watch keeps from step to step.
struct BlowUpWatch {
    bool started = false;
    bool rebase = false;          ///< set when the host put energy in (forces, impulses, bodies)
    std::size_t eventsFired = 0;  ///< explosions put energy in too
    std::int64_t since = 0;       ///< step of the reference
    double lowest = 0;            ///< J: the lowest total energy since the reference
    double allowance = 0;         ///< J: the growth over `lowest` that is not a blow-up
    double explicitGain = 0;      ///< J a step: explicit Euler's own gain in free fall
    std::vector<double> bodyAtLowest; ///< J: each body's energy when the total was lowest
    std::vector<double> bodyNow;      ///< J: scratch
};

/// One step's bodies as the watch reads them, after the step; static bodies (inverse mass 0)
/// are skipped.
struct BlowUpInputs {
    BodiesView bodies;
    std::span<const Shape> shapes; ///< by bodies.shapeOf: each body's bounding radius
    glm::vec3 gravity{0.0f};       ///< m/s^2
    float dt = 0;                  ///< s
    float baumgarte = 0;           ///< the solver's position correction per step, 0..1
    bool explicitEuler = false;
    std::size_t eventsFired = 0; ///< explosions fired so far
    std::int64_t step = 0;       ///< steps taken, this one included
};

/// A blow-up: the body that gained the most (or the joint's body b) and what happened.
struct BlowUp {
    std::uint32_t body = 0;
    std::string message;
};

/// Energy watch. Each dynamic body's energy is E = (v.P + w.L) / 2 - m g.x (kinetic plus
/// potential in uniform gravity); contacts, friction and joints can only lose the total, so it
/// never climbs far above its lowest value since the reference (the first step, or the last
/// step that fired an explosion or followed a force, impulse or body added by the host). The
/// allowance above it: kKineticShare of the kinetic energy at the reference, plus each body's
/// weight times the height of the scene along gravity and its own diameter, plus the energy of
/// the position correction pushing a body out by its diameter in one step
/// (m (2 beta r / dt)^2 / 2), plus, with explicit Euler, its own gain of m |g|^2 dt^2 / 2 a
/// step. Returns the body that gained the most when the total grew by more. O(bodies).
std::optional<BlowUp> watchEnergy(BlowUpWatch& watch, const BlowUpInputs& in);

/// Joint watch: the first joint whose anchors are further apart than kJointBreakRatio times the
/// sum of its bodies' bounding radii. O(joints).
std::optional<BlowUp> watchJoints(std::span<const Joint> joints, BodiesView bodies,
                                  std::span<const Shape> shapes, std::int64_t step);

} // namespace rubble
