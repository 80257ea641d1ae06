// host/viewer/scene_view.h: turns a world's state (live, or poses from a recording) into a
// DrawList: bodies coloured by body or by state, grounds, and the debug overlays.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "host/viewer/camera.h"
#include "host/viewer/draw_list.h"
#include "host/viewer/viewer.h"
#include "rubble/shared/body.h"
#include "rubble/world.h"

namespace rubble::viewer {

using shared::BodyPose;

enum class ColourMode {
    Body,  ///< each body its own colour
    State, ///< by state: asleep, debris (device), in contact, free, static
};

/// What the viewer shows besides the bodies.
struct Overlays {
    ColourMode colours = ColourMode::Body;
    bool contacts = false;  ///< contact points (World::contacts)
    bool normals = false;   ///< contact normals
    bool aabbs = false;     ///< each body's world-space bounding box
    bool joints = false;    ///< joint anchors, the lines to their bodies, hinge axes
    bool particles = false; ///< the particles of particle collision, where the world has them
};

/// Colours of the state mode, linear RGB.
namespace stateColour {
constexpr glm::vec3 kStatic{0.35f, 0.35f, 0.36f};
constexpr glm::vec3 kFree{0.80f, 0.74f, 0.60f};
constexpr glm::vec3 kContact{0.90f, 0.22f, 0.16f};
constexpr glm::vec3 kAsleep{0.28f, 0.38f, 0.62f};
constexpr glm::vec3 kDebris{0.95f, 0.55f, 0.10f};
} // namespace stateColour

/// The colour of body `index` in the by-body mode: hues spread by the golden ratio, linear RGB.
glm::vec3 bodyColour(std::uint32_t index);

/// The parts of a world that do not change as it steps, prepared once for drawing.
class SceneView {
  public:
    /// Reads shapes, names, flags and joints of the world in its current (initial) state, and
    /// the bounds of its bodies, which place the ground and the automatic camera.
    explicit SceneView(const World& world);

    /// Where the bodies are at the start, with the ground under them.
    const Bounds& bounds() const { return bounds_; }

    /// Fills `out` (cleared first) with the bodies at `poses` (one per body, by index).
    /// `live` is the world the poses come from, for contacts, sleep and particles; null for a
    /// recording, which has poses only.
    void build(std::span<const shared::BodyPose> poses, const World* live,
               const Overlays& overlays, DrawList& out) const;

    /// A body colour that replaces the by-body colour of body `index` (tests use pure colours).
    void setBodyColour(std::uint32_t index, glm::vec3 colour);
    glm::vec3 colourOf(std::uint32_t index) const { return colours_[index]; }

  private:
    struct JointView {
        std::uint32_t a, b;
        glm::vec3 anchorInA, anchorInB; ///< body frames, m
        glm::vec3 axisInA;              ///< hinge axis in a's frame; zero for ball joints
    };
    void addGrounds(std::span<const shared::BodyPose> poses, DrawList& out) const;
    void addAabbs(std::span<const shared::BodyPose> poses, DrawList& out) const;
    void addContacts(const std::vector<ContactInfo>& contacts, const Overlays& overlays,
                     DrawList& out) const;
    void addJoints(std::span<const shared::BodyPose> poses, DrawList& out) const;

    std::vector<ShapeGeometry> shapes_;
    std::vector<std::uint32_t> shapeOf_;
    std::vector<std::uint8_t> isStatic_, isDebris_;
    std::vector<glm::vec3> colours_;
    std::vector<JointView> joints_;
    Bounds bounds_;
    float markSize_ = 0.05f; // m: contact crosses, joint axes, scaled to the bodies
    mutable std::vector<std::uint8_t> inContact_;
};

/// The world's current poses through its public queries, which bring them back from the
/// device when the OpenCL backend holds them.
void currentPoses(const World& world, std::vector<shared::BodyPose>& out);

/// The overlays the command-line settings ask for.
Overlays toOverlays(const OverlaySettings& settings);

/// The camera of the command line, else one framing the scene's bounds at `aspect`.
Camera initialCamera(const std::optional<CameraSpec>& spec, const SceneView& view, float aspect);

/// The first line of the status overlay: step, time, bodies, contacts, residual, backend.
/// `step` and `time` are shown as given (a world rebuilt on another backend counts on).
std::string statusLine(std::int64_t step, double time, const World& world,
                       const std::string& backend, const std::string& device);
/// The status line of a recording: step, time, bodies and the file.
std::string replayLine(std::int64_t step, double time, const World& world,
                       const std::string& path);
/// The second: the last step's milliseconds, in total and per stage.
std::string stageLine(const StepStats& stats);

} // namespace rubble::viewer
