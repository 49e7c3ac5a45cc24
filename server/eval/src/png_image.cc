// PNG output and the mask / difference images (png_image.h).
#include <lixel/eval/png_image.h>
#include <lixel/png/rgb_png.h>

#include <algorithm>
#include <cstring>
#include <utility>

namespace lixel::eval {
namespace {

void Put(RgbImage& image, int x, int y, const std::uint8_t (&c)[3]) {
    std::memcpy(image.At(x, y), c, 3);
}

const std::uint8_t (&TruthColour(Truth t))[3] {
    switch (t) {
        case Truth::kLit:
            return Palette::kLit;
        case Truth::kShadow:
            return Palette::kShadow;
        case Truth::kUndecided:
            return Palette::kUndecided;
        case Truth::kEmpty:
            break;
    }
    return Palette::kEmpty;
}

}  // namespace

Result<bool> WritePng(const std::string& path, const RgbImage& image) {
    return png::WriteRgb(path, image.width, image.height, image.rgb);
}

Result<RgbImage> ReadPng(const std::string& path) {
    auto read = png::ReadRgb(path);
    if (!read) return read.error();
    RgbImage image;
    image.width = read->width;
    image.height = read->height;
    image.rgb = std::move(read->rgb);
    return image;
}

RgbImage MaskImage(const GroundTruth& truth, const Mask& mask) {
    RgbImage image(truth.width, truth.height);
    for (int y = 0; y < truth.height; ++y) {
        for (int x = 0; x < truth.width; ++x) {
            const std::size_t i = truth.Index(x, y);
            if (!truth.Visible(i)) {
                Put(image, x, y, Palette::kEmpty);
            } else {
                Put(image, x, y, mask.lit[i] >= kLitThreshold ? Palette::kLit : Palette::kShadow);
            }
        }
    }
    return image;
}

RgbImage TruthImage(const GroundTruth& truth) {
    RgbImage image(truth.width, truth.height);
    for (int y = 0; y < truth.height; ++y) {
        for (int x = 0; x < truth.width; ++x) {
            Put(image, x, y, TruthColour(truth.state[truth.Index(x, y)]));
        }
    }
    return image;
}

RgbImage DifferenceImage(const GroundTruth& truth, const Mask& mask) {
    RgbImage image(truth.width, truth.height);
    for (int y = 0; y < truth.height; ++y) {
        for (int x = 0; x < truth.width; ++x) {
            const std::size_t i = truth.Index(x, y);
            const Truth t = truth.state[i];
            if (t != Truth::kLit && t != Truth::kShadow) {
                Put(image, x, y, TruthColour(t));
                continue;
            }
            const bool lit = mask.lit[i] >= kLitThreshold;
            if (lit == (t == Truth::kLit)) {
                Put(image, x, y, TruthColour(t));
            } else {
                Put(image, x, y, lit ? Palette::kFalseLit : Palette::kFalseShadow);
            }
        }
    }
    return image;
}

RgbImage Shrink(const RgbImage& image, int max_side) {
    const int side = std::max(image.width, image.height);
    const int factor = std::max(1, (side + std::max(1, max_side) - 1) / std::max(1, max_side));
    if (factor == 1) return image;
    RgbImage out(image.width / factor, image.height / factor);
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                int sum = 0;
                for (int dy = 0; dy < factor; ++dy) {
                    for (int dx = 0; dx < factor; ++dx) {
                        sum += image.At(x * factor + dx, y * factor + dy)[c];
                    }
                }
                out.At(x, y)[c] = static_cast<std::uint8_t>(sum / (factor * factor));
            }
        }
    }
    return out;
}

RgbImage ImageGrid(const std::vector<RgbImage>& tiles, int columns, int gap) {
    if (tiles.empty()) return {};
    columns = std::max(1, std::min<int>(columns, static_cast<int>(tiles.size())));
    const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
    int tw = 0, th = 0;
    for (const RgbImage& t : tiles) {
        tw = std::max(tw, t.width);
        th = std::max(th, t.height);
    }
    RgbImage grid(columns * tw + (columns + 1) * gap, rows * th + (rows + 1) * gap, 255);
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        const int col = static_cast<int>(k) % columns;
        const int row = static_cast<int>(k) / columns;
        const int x0 = gap + col * (tw + gap);
        // Row 0 of the grid is at the top: our images count rows from the bottom.
        const int y0 = grid.height - (gap + row * (th + gap)) - th;
        const RgbImage& t = tiles[k];
        for (int y = 0; y < t.height; ++y) {
            std::memcpy(grid.At(x0, y0 + (th - t.height) + y), t.At(0, y),
                        static_cast<std::size_t>(3) * t.width);
        }
    }
    return grid;
}

}  // namespace lixel::eval
