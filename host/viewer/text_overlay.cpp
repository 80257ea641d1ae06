// host/viewer/text_overlay.cpp: stb_easy_font quads turned into triangles.
#include "host/viewer/text_overlay.h"

#include <string>

#include <stb/stb_easy_font.h>

namespace rubble::viewer {
namespace {

constexpr float kLineHeight = 12.0f; // px at scale 1, the font's own line spacing

// stb_easy_font writes x, y, z floats and four colour bytes per vertex, four vertices a quad.
struct GlyphVertex {
    float x, y, z;
    unsigned char rgba[4];
};
static_assert(sizeof(GlyphVertex) == 16);

} // namespace

glm::vec2 textSize(std::string_view text, float scale) {
    std::string copy(text); // the library takes a mutable string
    return scale * glm::vec2(float(stb_easy_font_width(copy.data())), kLineHeight);
}

void appendText(std::vector<OverlayVertex>& out, glm::vec2 origin, std::string_view text,
                glm::vec4 colour, float scale) {
    std::string copy(text);
    // About 270 bytes a character in the worst case, says the library.
    std::vector<GlyphVertex> quads(copy.size() * 80 + 16);
    const int count = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, quads.data(),
                                          int(quads.size() * sizeof(GlyphVertex)));
    out.reserve(out.size() + std::size_t(count) * 6);
    for (int q = 0; q < count; ++q) {
        const GlyphVertex* v = &quads[std::size_t(q) * 4];
        OverlayVertex c[4];
        for (int k = 0; k < 4; ++k) c[k] = {origin + scale * glm::vec2(v[k].x, v[k].y), colour};
        out.insert(out.end(), {c[0], c[1], c[2], c[0], c[2], c[3]});
    }
}

void appendRect(std::vector<OverlayVertex>& out, glm::vec2 lo, glm::vec2 hi, glm::vec4 colour) {
    const OverlayVertex a{lo, colour}, b{{hi.x, lo.y}, colour}, c{hi, colour},
        d{{lo.x, hi.y}, colour};
    out.insert(out.end(), {a, b, c, a, c, d});
}

} // namespace rubble::viewer
