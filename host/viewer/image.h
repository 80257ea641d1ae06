// host/viewer/image.h: an RGB image read back from a frame, and PNG files of it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rubble/error.h"

namespace rubble::viewer {

/// 8-bit RGB pixels, rows from the top of the picture down.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb; ///< width * height * 3 bytes

    /// The pixel at column x, row y (0 is the top row), as 0..255 values.
    glm::ivec3 at(int x, int y) const {
        const std::size_t i = 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

/// Writes a PNG. Errors: Io naming the path.
Status writePng(const std::string& path, const Image& image);

/// Reads a PNG (any channel count; the result is RGB). Errors: BadInput naming the path.
Result<Image> readPng(const std::string& path);

} // namespace rubble::viewer
