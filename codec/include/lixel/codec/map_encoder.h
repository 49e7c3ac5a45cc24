// Encodes an image's float32 texels as a coded map (docs/service.md, "Coded maps"). One encoder
// per stream or worker: it keeps one zstd compression context and reuses it for every image.
#pragma once

#include <lixel/codec/coded_map.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace lixel::codec {

struct EncodeOptions {
    Codec codec = Codec::kQuantised;  // kQuantised is for depth only
    int bits = 24;                    // quantised: N in [16, 24]
    int zstd_level = 1;               // zstd's, [1, 19]: 1 is its fastest
    int tile = 64;                    // tile side, [8, 1024]
    std::uint64_t frame_id = 1;       // non-zero
    // A previous frame's decoded values (what the client holds): tiles whose values it predicts
    // better are sent as differences from it. Ignored unless it matches the image's content,
    // codec, N and size. Null: a keyframe.
    const IntegerImage* reference = nullptr;
    // Quantised only: each tile's shift in [0, kMaxTileShift], tiles in walk order (rows of
    // tiles from the bottom, each from the left). A tile of shift s steps by 2^s of N's, within
    // QuantisedErrorBound(N, s) of its texels. Empty: every tile at N's own step.
    std::vector<std::uint8_t> tile_shifts;
};

struct EncodedMap {
    std::string bytes;  // header + zstd payload
    CodedHeader header;
    IntegerImage decoded;  // the values a decoder will hold afterwards (the next reference)
    std::uint64_t temporal_tiles = 0;  // kTemporal and kCopy tiles
    std::uint64_t tiles = 0;
};

class MapEncoder {
  public:
    MapEncoder();
    ~MapEncoder();
    MapEncoder(const MapEncoder&) = delete;
    MapEncoder& operator=(const MapEncoder&) = delete;

    // `texels`: width * height * channels float32, channels interleaved, row 0 at the bottom.
    // Errors name the option (codec.bits, codec.tile, ...) or the image's shape.
    Result<EncodedMap> Encode(Content content, const float* texels, std::uint32_t width,
                              std::uint32_t height, const EncodeOptions& options);

  private:
    struct Context;
    std::unique_ptr<Context> context_;
};

}  // namespace lixel::codec
