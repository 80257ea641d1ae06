// host/viewer/draw_list.h: what one frame shows, independent of where the poses came from (a live
// World or a recorded trajectory): body instances by shape, grounds, lines, particles, text.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace rubble::viewer {

/// One body to draw: 48 bytes, the layout of the renderer's instance buffer.
struct BodyInstance {
    glm::vec4 position;    ///< centre of mass, world, m (w unused)
    glm::vec4 orientation; ///< unit quaternion (x, y, z, w), body to world
    glm::vec4 colour;      ///< linear RGB, a unused
};
static_assert(sizeof(BodyInstance) == 48);

/// A plane drawn as a finite square of ground with a grid on it.
struct GroundPlane {
    glm::vec3 normal{0, 1, 0}; ///< unit, out of the solid
    glm::vec3 centre{0.0f};    ///< a point on the plane at the middle of the square, m
    float halfSize = 50.0f;    ///< m
};

/// One end of a line segment: 28 bytes, the layout of the renderer's line buffer.
struct LineVertex {
    glm::vec3 position; ///< world, m
    glm::vec4 colour;   ///< linear RGB and alpha
};
static_assert(sizeof(LineVertex) == 28);

/// Everything one frame shows.
struct DrawList {
    std::vector<std::vector<BodyInstance>> instances; ///< by shape index
    std::vector<GroundPlane> grounds;
    std::vector<LineVertex> lines;
    std::vector<glm::vec4> particles; ///< xyz world position, w radius, m
    std::vector<std::string> text;    ///< lines of the status overlay, top left
    std::string message;              ///< an error or notice, drawn highlighted under the text

    /// Empties every list, keeping their storage.
    void clear() {
        for (std::vector<BodyInstance>& v : instances) v.clear();
        grounds.clear();
        lines.clear();
        particles.clear();
        text.clear();
        message.clear();
    }
    /// Adds a segment from a to b.
    void line(glm::vec3 a, glm::vec3 b, glm::vec4 colour) {
        lines.push_back({a, colour});
        lines.push_back({b, colour});
    }
};

} // namespace rubble::viewer
