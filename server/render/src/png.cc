// PNG previews of render images, through lixel::png.
#include <lixel/png/rgb_png.h>
#include <lixel/render/image_io.h>

#include <algorithm>
#include <string>
#include <utility>

namespace lixel::render {

Result<bool> WritePng(const std::string& path, const Rgb8Image& image) {
    return png::WriteRgb(path, image.width, image.height, image.pixels);
}

Result<Rgb8Image> ReadPng(const std::string& path) {
    auto read = png::ReadRgb(path);
    if (!read) return read.error();
    return Rgb8Image{read->width, read->height, std::move(read->rgb)};
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
