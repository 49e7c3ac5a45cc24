// 8-bit RGB PNG files (rgb_png.h).
#include <lixel/png/rgb_png.h>
#include <png.h>

#include <cstring>

namespace lixel::png {
namespace {

png_image Blank() {
    png_image image;
    std::memset(&image, 0, sizeof(image));
    image.version = PNG_IMAGE_VERSION;
    return image;
}

}  // namespace

Result<bool> WriteRgb(const std::string& path, int width, int height,
                      std::span<const std::uint8_t> rgb) {
    if (width < 1 || height < 1 || rgb.size() != std::size_t{3} * width * height) {
        return Error{path, "image is empty or its pixel buffer is not 3 * width * height bytes"};
    }
    png_image image = Blank();
    image.width = static_cast<png_uint_32>(width);
    image.height = static_cast<png_uint_32>(height);
    image.format = PNG_FORMAT_RGB;
    // A negative row stride hands libpng the rows top first.
    const png_int_32 stride = -static_cast<png_int_32>(PNG_IMAGE_ROW_STRIDE(image));
    if (!png_image_write_to_file(&image, path.c_str(), 0, rgb.data(), stride, nullptr)) {
        return Error{path, std::string("cannot write PNG: ") + image.message};
    }
    return true;
}

Result<RgbPixels> ReadRgb(const std::string& path) {
    png_image image = Blank();
    if (!png_image_begin_read_from_file(&image, path.c_str())) {
        return Error{path, std::string("cannot read PNG: ") + image.message};
    }
    image.format = PNG_FORMAT_RGB;
    RgbPixels out;
    out.width = static_cast<int>(image.width);
    out.height = static_cast<int>(image.height);
    out.rgb.resize(PNG_IMAGE_SIZE(image));
    const png_int_32 stride = -static_cast<png_int_32>(PNG_IMAGE_ROW_STRIDE(image));
    if (!png_image_finish_read(&image, nullptr, out.rgb.data(), stride, nullptr)) {
        return Error{path, std::string("cannot decode PNG: ") + image.message};
    }
    return out;
}

}  // namespace lixel::png
