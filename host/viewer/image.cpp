// host/viewer/image.cpp: PNG files through stb_image_write and stb_image (Debian's libstb).
#include "host/viewer/image.h"

#include <cstring>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace rubble::viewer {

Status writePng(const std::string& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != std::size_t(image.width) * std::size_t(image.height) * 3)
        return makeError(ErrorKind::Internal, path, "the image has no pixels");
    // Level 9 (of zlib's 0..9) keeps the pictures small enough to commit.
    stbi_write_png_compression_level = 9;
    if (!stbi_write_png(path.c_str(), image.width, image.height, 3, image.rgb.data(),
                        image.width * 3))
        return makeError(ErrorKind::Io, path, "cannot write the PNG file");
    return {};
}

Result<Image> readPng(const std::string& path) {
    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
    if (!data) {
        const char* why = stbi_failure_reason();
        return makeError(ErrorKind::BadInput, path,
                         std::string("not a readable PNG file (") + (why ? why : "?") + ")");
    }
    Image image;
    image.width = w;
    image.height = h;
    image.rgb.assign(data, data + std::size_t(w) * std::size_t(h) * 3);
    stbi_image_free(data);
    return image;
}

} // namespace rubble::viewer
