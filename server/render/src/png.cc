// 8-bit RGB PNG through libpng's simplified API.
#include <lixel/render/image_io.h>
#include <png.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace lixel::render {

Result<bool> WritePng(const std::string& path, const Rgb8Image& image) {
    if (image.width < 1 || image.height < 1 ||
        image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
        return Error{"image", "PNG takes width * height * 3 bytes"};
    }
    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = PNG_FORMAT_RGB;
    // Negative row stride: our rows are bottom first, PNG's top first.
    const png_int_32 stride = -static_cast<png_int_32>(image.width * 3);
    if (!png_image_write_to_file(&png, path.c_str(), 0, image.pixels.data(), stride, nullptr)) {
        return Error{"path", path + ": " + png.message};
    }
    return true;
}

Result<Rgb8Image> ReadPng(const std::string& path) {
    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path.c_str())) {
        return Error{"path", path + ": " + png.message};
    }
    png.format = PNG_FORMAT_RGB;
    Rgb8Image image;
    image.width = static_cast<int>(png.width);
    image.height = static_cast<int>(png.height);
    image.pixels.resize(PNG_IMAGE_SIZE(png));
    const png_int_32 stride = -static_cast<png_int_32>(image.width * 3);
    if (!png_image_finish_read(&png, nullptr, image.pixels.data(), stride, nullptr)) {
        return Error{"path", path + ": " + png.message};
    }
    return image;
}

Rgb8Image MaskPreview(const FloatImage& mask) {
    Rgb8Image out{mask.width, mask.height, {}};
    out.pixels.resize(static_cast<std::size_t>(mask.width) * mask.height * 3);
    for (int y = 0; y < mask.height; ++y) {
        for (int x = 0; x < mask.width; ++x) {
            const float v = mask.at(x, y);
            std::uint8_t* p = &out.pixels[(static_cast<std::size_t>(y) * mask.width + x) * 3];
            if (v < 0.0f) {
                p[0] = 40;
                p[1] = 60;
                p[2] = 140;
            } else {
                const auto g = static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
                p[0] = p[1] = p[2] = g;
            }
        }
    }
    return out;
}

}  // namespace lixel::render
