// 8-bit RGB PNG files through libpng's simplified API. Every lixel image numbers its rows from
// the bottom (row 0 at the bottom, as glReadPixels and the viewport matrix do); PNG stores the
// top row first, so rows are flipped on write and on read.
#pragma once

#include <lixel/solver/result.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace lixel::png {

struct RgbPixels {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  // 3 * width * height, row 0 at the bottom
};

// Errors name the path: an empty image, a buffer that is not 3 * width * height bytes, or what
// libpng (or the file system, through it) reported.
Result<bool> WriteRgb(const std::string& path, int width, int height,
                      std::span<const std::uint8_t> rgb);

// Reads any PNG libpng decodes to 8-bit RGB (grey is expanded, alpha removed by libpng).
Result<RgbPixels> ReadRgb(const std::string& path);

}  // namespace lixel::png
