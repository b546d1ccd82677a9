// 8-bit RGB images as PNG bytes (stb_image_write, our own static copy: consumers may
// link theirs): the preview's frames and the wave field's plot. The core component.
#include "libwave/errors.h"
#include "libwave/io.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include <string>

namespace wave {

std::string png_bytes(const Image& image) {
    if (image.rgb.size() != 3 * image.width * image.height || image.width == 0 || image.height == 0)
        throw InputError("png: the image's pixels do not match its size");
    std::string bytes;
    const auto sink = [](void* ctx, void* data, int size) {
        static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(sink, &bytes, static_cast<int>(image.width), static_cast<int>(image.height), 3, image.rgb.data(),
                                static_cast<int>(3 * image.width)))
        throw RuntimeError("png: could not encode the image");
    return bytes;
}

void write_png(const Image& image, const std::string& path) { write_file_atomic(path, png_bytes(image)); }

}  // namespace wave
