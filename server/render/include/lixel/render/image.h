// Images as they leave the GPU: float maps and masks, 8-bit previews. Row 0 is the bottom row
// (GL order: lixel or pixel y in [0, 1) is row 0), so image (x, y) is lixel (x, y).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lixel::render {

struct FloatImage {
    int width = 0;
    int height = 0;
    int channels = 1;           // 1 (depth, mask) or 2 (silhouette points), up to 4
    std::vector<float> pixels;  // width * height * channels, row 0 at the bottom

    float at(int x, int y, int c = 0) const {
        return pixels[(static_cast<std::size_t>(y) * width + x) * channels + c];
    }
};

struct Rgb8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;  // width * height * 3, row 0 at the bottom
};

}  // namespace lixel::render
