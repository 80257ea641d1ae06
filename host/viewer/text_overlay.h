// host/viewer/text_overlay.h: screen-space text from stb_easy_font's bitmap glyphs, as coloured
// triangles in pixels from the top-left corner, with a translucent backdrop.
#pragma once

#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace rubble::viewer {

/// One overlay vertex: 24 bytes, the layout of the renderer's overlay buffer.
struct OverlayVertex {
    glm::vec2 pixel;  ///< from the top-left corner, px
    glm::vec4 colour; ///< sRGB and alpha, as written to the frame
};
static_assert(sizeof(OverlayVertex) == 24);

/// Size of one line of text at a scale, px: the font is 7 px tall on a 12 px line at scale 1.
glm::vec2 textSize(std::string_view text, float scale);

/// Appends the triangles of one line of text with its top-left corner at `origin`.
void appendText(std::vector<OverlayVertex>& out, glm::vec2 origin, std::string_view text,
                glm::vec4 colour, float scale);

/// Appends a filled rectangle.
void appendRect(std::vector<OverlayVertex>& out, glm::vec2 lo, glm::vec2 hi, glm::vec4 colour);

} // namespace rubble::viewer
