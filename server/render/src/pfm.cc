// Portable float maps (Debevec's PFM): text header, raw little-endian floats, bottom row first.
#include <lixel/render/image_io.h>

#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

namespace lixel::render {
namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

float ByteSwapped(float v) {
    const std::uint32_t b = std::bit_cast<std::uint32_t>(v);
    return std::bit_cast<float>((b >> 24) | ((b >> 8) & 0xff00u) | ((b << 8) & 0xff0000u) |
                                (b << 24));
}

}  // namespace

Result<bool> WritePfm(const std::string& path, const FloatImage& image) {
    if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 3 ||
        image.pixels.size() != static_cast<std::size_t>(image.width) * image.height *
                                   static_cast<std::size_t>(image.channels)) {
        return Error{"image", "PFM takes 1 to 3 channels with width * height * channels values"};
    }
    File f(std::fopen(path.c_str(), "wb"));
    if (!f) return Error{"path", path + ": " + std::strerror(errno)};
    const int out_channels = image.channels == 1 ? 1 : 3;
    // Negative scale: little-endian samples.
    std::fprintf(f.get(), "%s\n%d %d\n-1.0\n", out_channels == 1 ? "Pf" : "PF", image.width,
                 image.height);
    std::vector<float> row(static_cast<std::size_t>(image.width) * out_channels, 0.0f);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            for (int c = 0; c < image.channels; ++c) {
                float v = image.at(x, y, c);
                if constexpr (std::endian::native == std::endian::big) {
                    v = ByteSwapped(v);
                }
                row[static_cast<std::size_t>(x) * out_channels + c] = v;
            }
        }
        if (std::fwrite(row.data(), sizeof(float), row.size(), f.get()) != row.size()) {
            return Error{"path", path + ": write failed"};
        }
    }
    if (std::fflush(f.get()) != 0) return Error{"path", path + ": write failed"};
    return true;
}

Result<FloatImage> ReadPfm(const std::string& path) {
    File f(std::fopen(path.c_str(), "rb"));
    if (!f) return Error{"path", path + ": " + std::strerror(errno)};
    char kind[3] = {};
    int width = 0;
    int height = 0;
    double scale = 0.0;
    if (std::fscanf(f.get(), "%2s %d %d %lf", kind, &width, &height, &scale) != 4 ||
        std::fgetc(f.get()) == EOF) {
        return Error{"path", path + ": not a PFM header"};
    }
    const int channels = std::strcmp(kind, "Pf") == 0 ? 1 : std::strcmp(kind, "PF") == 0 ? 3 : 0;
    if (channels == 0 || width < 1 || height < 1 || scale == 0.0 || !std::isfinite(scale)) {
        return Error{"path", path + ": not a PFM header"};
    }
    FloatImage image{width, height, channels, {}};
    image.pixels.resize(static_cast<std::size_t>(width) * height * channels);
    if (std::fread(image.pixels.data(), sizeof(float), image.pixels.size(), f.get()) !=
        image.pixels.size()) {
        return Error{"path", path + ": truncated PFM data"};
    }
    const bool little = scale < 0.0;
    if (little != (std::endian::native == std::endian::little)) {
        for (float& v : image.pixels) {
            v = ByteSwapped(v);
        }
    }
    return image;
}

}  // namespace lixel::render
