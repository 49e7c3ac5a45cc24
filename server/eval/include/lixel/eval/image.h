// Per-pixel images shared by ground truth, metrics and the report. Row 0 is the bottom row
// (pixel y in [0, 1)), as the viewport matrix and glReadPixels number rows; PNG writers flip.
#pragma once

#include <lixel/solver/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lixel::eval {

// A method's answer per viewer pixel: the lit fraction in [0, 1] (1 = fully lit). Metrics
// threshold it at kLitThreshold, so hard masks (0/1) and filtered ones (PCF) both work.
struct Mask {
    int width = 0;
    int height = 0;
    std::vector<float> lit;  // width * height, row 0 at the bottom

    float At(int x, int y) const { return lit[static_cast<std::size_t>(y) * width + x]; }
};

// A lit fraction at or above this counts as lit.
inline constexpr float kLitThreshold = 0.5f;

// An 8-bit RGB image for PNG output, row 0 at the bottom like every image here.
struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  // 3 * width * height

    RgbImage() = default;
    RgbImage(int w, int h, std::uint8_t fill = 0)
        : width(w), height(h), rgb(static_cast<std::size_t>(3) * w * h, fill) {}
    std::uint8_t* At(int x, int y) { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
    const std::uint8_t* At(int x, int y) const {
        return &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
    }
};

}  // namespace lixel::eval
