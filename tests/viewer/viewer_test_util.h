// tests/viewer/viewer_test_util.h: helpers of the viewer tests: a GL context or a clear reason
// there is none (a failure when CI is set), and colour checks on rendered pixels.
#pragma once

#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "host/viewer/image.h"
#include "support/ci.h" // inCi: in CI a test may not skip for want of OpenGL or a display

namespace rubble::test {

/// A pixel as linear RGB in [0, 1] (the frame is written with a gamma of 2.2).
inline glm::vec3 linearPixel(const viewer::Image& image, int x, int y) {
    const glm::vec3 srgb = glm::vec3(image.at(x, y)) / 255.0f;
    return glm::pow(srgb, glm::vec3(2.2f));
}

/// The share of each channel in the colour: the hue and saturation without the brightness.
inline glm::vec3 chromaticity(glm::vec3 c) {
    const float sum = c.r + c.g + c.b;
    return sum > 1e-4f ? c / sum : glm::vec3(1.0f / 3.0f);
}

/// Whether a lit pixel shows a surface of `colour` (linear RGB): the same channel shares within
/// `tolerance`, whatever the lighting did to its brightness.
inline bool looksLike(const viewer::Image& image, int x, int y, glm::vec3 colour,
                      float tolerance = 0.07f) {
    const glm::vec3 c = chromaticity(linearPixel(image, x, y));
    const glm::vec3 want = chromaticity(colour);
    return glm::all(glm::lessThan(glm::abs(c - want), glm::vec3(tolerance)));
}

/// Text for a failed pixel check.
inline std::string describePixel(const viewer::Image& image, int x, int y) {
    const glm::ivec3 p = image.at(x, y);
    return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") = (" +
           std::to_string(p.r) + ", " + std::to_string(p.g) + ", " + std::to_string(p.b) + ")";
}

/// Number of distinct colours in an image (a blank frame has one).
inline std::size_t distinctColours(const viewer::Image& image) {
    std::vector<std::uint32_t> seen;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const glm::ivec3 p = image.at(x, y);
            seen.push_back(std::uint32_t(p.r) << 16 | std::uint32_t(p.g) << 8 | std::uint32_t(p.b));
        }
    std::sort(seen.begin(), seen.end());
    return std::size_t(std::unique(seen.begin(), seen.end()) - seen.begin());
}

} // namespace rubble::test
