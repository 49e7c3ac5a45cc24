// A frame's maps as they arrive (map_stream.h).
#include "map_stream.h"

#include <cstring>

namespace lixel::client {
namespace {

// An image's size as float32, from its announced shape (sides checked first: at most
// codec::kMaxSide, so the product fits).
std::uint64_t RawBytes(const v1::MapImage& image) {
    return std::uint64_t{image.width()} * image.height() *
           (image.pass() == v1::PASS_SILHOUETTE_MAP ? 8 : 4);
}

// What is wrong with a Render header (a broken or hostile server), or "": every image's shape
// within the largest a map has, raw images' sizes their shapes', coded images only when asked
// for, and the sum of their float32 sizes within the client's receive limit.
std::string CheckHeader(const v1::RenderHeader& header, bool coding, std::uint64_t limit) {
    std::uint64_t announced = 0;
    for (int i = 0; i < header.images_size(); ++i) {
        const v1::MapImage& image = header.images(i);
        const std::string field = "images[" + std::to_string(i) + "]: ";
        const std::string shape =
            std::to_string(image.width()) + " x " + std::to_string(image.height());
        if (image.width() < 1 || image.width() > codec::kMaxSide || image.height() < 1 ||
            image.height() > codec::kMaxSide) {
            return field + shape + " is outside [1, 16385]²";
        }
        if (image.coded() && !coding) return field + "coded, but no encoding was asked for";
        if (!image.coded() && image.bytes() != RawBytes(image)) {
            return field + std::to_string(image.bytes()) + " bytes announced for " + shape +
                   ", which has " + std::to_string(RawBytes(image));
        }
        announced += RawBytes(image);
    }
    if (announced > limit) {
        return "header: " + std::to_string(announced) +
               " bytes of maps announced, over max_receive_bytes = " + std::to_string(limit);
    }
    return "";
}

}  // namespace

std::string MapStream::Header(const v1::RenderHeader& header) {
    if (has_header_) return "header: a second header in one stream";
    has_header_ = true;
    maps_.header = header;
    // Checked before anything is allocated for the images.
    if (std::string why = CheckHeader(maps_.header, coding_, limit_); !why.empty()) return why;
    for (const v1::MapImage& image : maps_.header.images()) {
        maps_.images.emplace_back(image.coded() ? 0 : image.bytes() / sizeof(float));
        total_ += image.bytes();
    }
    coded_.resize(maps_.images.size());
    raw_bytes_.assign(maps_.images.size(), 0);
    return "";
}

std::string MapStream::Chunk(const v1::MapChunk& piece) {
    if (piece.image_index() >= maps_.images.size()) {
        return "chunk: image_index " + std::to_string(piece.image_index()) +
               " names no image of the header";
    }
    maps_.streamed_bytes += piece.data().size();
    const v1::MapImage& announced = maps_.header.images(static_cast<int>(piece.image_index()));
    if (announced.coded()) {
        // Coded bytes arrive in order, each image within its bound.
        std::string& bytes = coded_[piece.image_index()];
        const std::uint64_t limit = codec::MaxCodedBytes(RawBytes(announced));
        if (piece.offset() != bytes.size() || bytes.size() + piece.data().size() > limit) {
            return "images[" + std::to_string(piece.image_index()) + "]: coded chunk at " +
                   std::to_string(piece.offset()) + " is out of order or past the image's " +
                   std::to_string(limit) + "-byte bound";
        }
        bytes += piece.data();
        return "";
    }
    auto& image = maps_.images[piece.image_index()];
    const std::size_t bytes = image.size() * sizeof(float);
    // Both sides checked apart: offset + size can wrap around past 2^64.
    if (piece.offset() > bytes || piece.data().size() > bytes - piece.offset()) {
        return "images[" + std::to_string(piece.image_index()) + "]: chunk at " +
               std::to_string(piece.offset()) + " runs past the image's " + std::to_string(bytes) +
               " bytes";
    }
    std::memcpy(reinterpret_cast<char*>(image.data()) + piece.offset(), piece.data().data(),
                piece.data().size());
    raw_bytes_[piece.image_index()] += piece.data().size();
    return "";
}

std::string MapStream::Incomplete() const {
    if (!has_header_) return "no header before the frame's end";
    for (int i = 0; i < maps_.header.images_size(); ++i) {
        const v1::MapImage& image = maps_.header.images(i);
        if (image.coded()) continue;  // the decoder checks a coded image's size
        if (raw_bytes_[static_cast<std::size_t>(i)] != image.bytes()) {
            return "images[" + std::to_string(i) +
                   "]: " + std::to_string(raw_bytes_[static_cast<std::size_t>(i)]) + " of its " +
                   std::to_string(image.bytes()) + " bytes arrived";
        }
    }
    return "";
}

Result<RenderedMaps> MapStream::Finish(CodedFrames& decoder) {
    if (!coding_) return std::move(maps_);
    std::vector<codec::IntegerImage> held;
    for (int i = 0; i < maps_.header.images_size(); ++i) {
        if (!maps_.header.images(i).coded()) continue;
        auto decoded = decoder.Decode(maps_.header, i, coded_[static_cast<std::size_t>(i)]);
        if (!decoded) return decoded.error();
        maps_.images[static_cast<std::size_t>(i)] = std::move(decoded->texels);
        maps_.coded.push_back(decoded->header);
        held.push_back(std::move(decoded->values));
    }
    decoder.Hold(std::move(held));
    return std::move(maps_);
}

}  // namespace lixel::client
