// PNG output and the mask / difference images (png_image.h).
#include <lixel/eval/png_image.h>
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace lixel::eval {
namespace {

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f) std::fclose(f);
    }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

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
    if (image.width < 1 || image.height < 1 ||
        image.rgb.size() != static_cast<std::size_t>(3) * image.width * image.height) {
        return Error{path, "image is empty or its pixel buffer does not match its size"};
    }
    File file(std::fopen(path.c_str(), "wb"));
    if (!file) return Error{path, std::string("cannot open for writing: ") + std::strerror(errno)};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    if (!png) return Error{path, "png_create_write_struct failed"};
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return Error{path, "png_create_info_struct failed"};
    }
    std::vector<png_bytep> rows(image.height);
    for (int y = 0; y < image.height; ++y) {
        // PNG rows go top to bottom; ours bottom to top.
        rows[y] = const_cast<png_bytep>(image.At(0, image.height - 1 - y));
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return Error{path, "libpng failed while writing"};
    }
    png_init_io(png, file.get());
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
                 static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (std::fflush(file.get()) != 0) {
        return Error{path, std::string("write failed: ") + std::strerror(errno)};
    }
    return true;
}

Result<RgbImage> ReadPng(const std::string& path) {
    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path.c_str())) {
        return Error{path, std::string("cannot read PNG: ") + png.message};
    }
    png.format = PNG_FORMAT_RGB;
    RgbImage image(static_cast<int>(png.width), static_cast<int>(png.height));
    // Negative stride: libpng writes the top row last, so row 0 ends up at the bottom.
    const png_int_32 stride = -static_cast<png_int_32>(PNG_IMAGE_ROW_STRIDE(png));
    if (!png_image_finish_read(&png, nullptr, image.rgb.data(), stride, nullptr)) {
        return Error{path, std::string("cannot decode PNG: ") + png.message};
    }
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
