// OpenEXR float images through the RGBA-agnostic framebuffer API.
#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <lixel/render/image_io.h>

#include <array>
#include <string>

namespace lixel::render {
namespace {

std::array<const char*, 4> ChannelNames(int channels) {
    if (channels == 1) return {"Y", nullptr, nullptr, nullptr};
    return {"R", "G", "B", "A"};
}

}  // namespace

Result<bool> WriteExr(const std::string& path, const FloatImage& image) {
    if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 4 ||
        image.pixels.size() != static_cast<std::size_t>(image.width) * image.height *
                                   static_cast<std::size_t>(image.channels)) {
        return Error{"image", "EXR takes 1 to 4 channels with width * height * channels values"};
    }
    try {
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        const auto names = ChannelNames(image.channels);
        for (int c = 0; c < image.channels; ++c) {
            header.channels().insert(names[static_cast<std::size_t>(c)], Imf::Channel(Imf::FLOAT));
        }
        // EXR rows run top to bottom: flip our bottom-first rows by pointing at the last row
        // with a negative y stride.
        const std::size_t row = static_cast<std::size_t>(image.width) * image.channels;
        const float* last_row = image.pixels.data() + row * (image.height - 1);
        Imf::FrameBuffer frame;
        for (int c = 0; c < image.channels; ++c) {
            frame.insert(names[static_cast<std::size_t>(c)],
                         Imf::Slice(Imf::FLOAT,
                                    const_cast<char*>(reinterpret_cast<const char*>(last_row + c)),
                                    sizeof(float) * image.channels,
                                    -static_cast<std::ptrdiff_t>(sizeof(float) * row)));
        }
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        return Error{"path", path + ": " + e.what()};
    }
    return true;
}

Result<FloatImage> ReadExr(const std::string& path) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        FloatImage image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        const Imf::ChannelList& list = file.header().channels();
        if (list.findChannel("Y") != nullptr) {
            image.channels = 1;
        } else {
            image.channels = 0;
            for (const char* n : {"R", "G", "B", "A"}) {
                if (list.findChannel(n) == nullptr) break;
                ++image.channels;
            }
        }
        if (image.channels == 0) return Error{"path", path + ": no Y or R channel"};
        const auto names = ChannelNames(image.channels);
        const std::size_t row = static_cast<std::size_t>(image.width) * image.channels;
        image.pixels.resize(row * image.height);
        float* last_row = image.pixels.data() + row * (image.height - 1);
        Imf::FrameBuffer frame;
        for (int c = 0; c < image.channels; ++c) {
            // The slice base is where pixel (0, 0) of the data window would sit.
            char* base =
                reinterpret_cast<char*>(last_row + c) -
                static_cast<std::ptrdiff_t>(sizeof(float)) * image.channels * window.min.x +
                static_cast<std::ptrdiff_t>(sizeof(float) * row) * window.min.y;
            frame.insert(names[static_cast<std::size_t>(c)],
                         Imf::Slice(Imf::FLOAT, base, sizeof(float) * image.channels,
                                    -static_cast<std::ptrdiff_t>(sizeof(float) * row)));
        }
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const std::exception& e) {
        return Error{"path", path + ": " + e.what()};
    }
}

}  // namespace lixel::render
