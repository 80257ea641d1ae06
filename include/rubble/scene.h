// include/rubble/scene.h: a scene file parsed and checked (SCENE_FORMAT.md, version 1), before
// any shape is built. Generators are expanded; names are resolved to indices.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/error.h"
#include "rubble/options.h"

namespace rubble {

/// Surface properties; per contact, friction combines as sqrt(mu_a mu_b) and restitution as
/// max(e_a, e_b).
struct MaterialDesc {
    std::string name;
    float friction = 0.5f;    ///< Coulomb coefficient, >= 0
    float restitution = 0.0f; ///< 0..1
};

/// Shortest and longest sizes a scene may give (half extents, radii, the extent of a convex or
/// mesh shape, the particle spacing), m: within them a body's volume, mass and inertia and the
/// products the narrow phase forms stay normal single-precision numbers.
inline constexpr double kMinLength = 1e-4;
inline constexpr double kMaxLength = 1e5;

enum class ShapeType { Box, Sphere, Convex, Mesh, Plane, Capsule };

/// A height field's grid as the file gives it: heights[row * columns + column], rows along z and
/// columns along x, centred on the body's position.
struct HeightFieldDesc {
    std::uint32_t rows = 0, columns = 0; ///< at least 2 each
    std::vector<float> heights;          ///< m, rows x columns, row by row
    glm::vec2 spacing{1.0f};             ///< between columns (x) and rows (z), m
    std::string file;                    ///< the PNG it was read from, if any
};

/// A named shape as the file gives it. Vertices are still in the file's frame: the centre of
/// mass is moved to the origin when the world is built.
struct ShapeDesc {
    std::string name;
    ShapeType type = ShapeType::Box;
    std::string where;               ///< `file: shapes.<name>`, for errors
    glm::vec3 halfExtents{0.5f};     ///< box, m
    float radius = 0.5f;             ///< sphere and capsule, m
    float halfHeight = 0.5f;         ///< capsule: half the length of its segment (local y), m
    std::vector<glm::vec3> points;   ///< convex: its vertices; mesh: the OBJ's vertices, scaled, m
    std::vector<glm::uvec3> triangles; ///< mesh: the OBJ's faces as triangles
    std::string file;                ///< mesh: the OBJ path as resolved against the scene's folder
    float scale = 1.0f;              ///< mesh: uniform scale applied to the OBJ
    glm::vec3 normal{0.0f, 1.0f, 0.0f}; ///< plane: unit normal pointing out of the solid
    float offset = 0.0f;             ///< plane: dot(normal, x) = offset on the surface, m
    /// heightfield: its grid. The shape is then a mesh (type Mesh) of the grid's triangles, two
    /// to a cell, in `points` and `triangles`; static bodies only.
    std::optional<HeightFieldDesc> heightField;
};

/// One body, from `bodies` or from a generator.
struct BodyDesc {
    std::string name;
    std::string where;                 ///< `file: bodies[3]` or `file: generators[0] (d17)`
    std::uint32_t shape = 0;           ///< index into Scene::shapes
    std::uint32_t material = 0;        ///< index into Scene::materials
    bool isStatic = false;
    /// Moved by its velocities (or a target pose from the host), never by forces or contacts:
    /// infinite mass, no mass or density.
    bool isKinematic = false;
    bool debris = false;
    std::optional<float> mass;         ///< kg
    std::optional<float> density;      ///< kg/m^3
    glm::vec3 position{0.0f};          ///< centre of mass, world, m
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f}; ///< unit, body to world
    glm::vec3 linearVelocity{0.0f};    ///< m/s
    glm::vec3 angularVelocity{0.0f};   ///< rad/s, world frame
};

enum class JointType { Ball, Hinge };

/// A joint between two bodies; anchor and axis in world space at the initial pose.
struct JointDesc {
    JointType type = JointType::Ball;
    std::string where;
    std::uint32_t a = 0, b = 0;        ///< body indices
    glm::vec3 anchor{0.0f};            ///< m
    glm::vec3 axis{1.0f, 0.0f, 0.0f};  ///< hinge only, unit
};

/// A radial impulse: every dynamic body within radius gets impulse * (1 - d / radius) N s away
/// from the centre, at its centre of mass, at the first step whose time is >= time.
struct EventDesc {
    std::string where;
    float time = 0.0f;          ///< s
    glm::vec3 centre{0.0f};     ///< m
    float impulse = 0.0f;       ///< N s at the centre
    float radius = 1.0f;        ///< m
};

/// A whole scene.
struct Scene {
    std::string file;  ///< the path it was read from, as given
    std::string name;
    SimulationOptions simulation;
    std::vector<MaterialDesc> materials; ///< index 0 is "default"
    std::vector<ShapeDesc> shapes;
    std::vector<BodyDesc> bodies;
    std::vector<JointDesc> joints;
    std::vector<EventDesc> events;

    /// Index of the body with that name, if any.
    std::optional<std::uint32_t> findBody(std::string_view name) const;
};

/// The fields a scene file may have at its top level (docs/scene-format.md); any other is refused.
inline constexpr std::string_view kSceneKeys[] = {"format",    "version", "name",   "simulation",
                                                  "materials", "shapes",  "bodies", "generators",
                                                  "joints",    "events"};

/// Reads and checks a scene file. Errors are BadInput (or NotSupported) naming the file and the
/// JSON path of the field, for example `scenes/a.json: bodies[3].mass: must be > 0, got -1`.
Result<Scene> loadScene(const std::string& path);

/// Parses scene text; `file` names it in errors and `baseDir` resolves mesh paths.
Result<Scene> parseScene(std::string_view text, const std::string& file,
                         const std::string& baseDir);

} // namespace rubble
