// Decodes coded maps (docs/service.md, "Coded maps"), refusing corrupt, truncated or mismatched
// input with an error that names the field: every size is checked against the header and the
// caller's budget before anything is allocated, the header carries a CRC-32 and the payload
// zstd's content checksum, and a frame whose reference is not held is refused, never decoded
// against another frame.
#pragma once

#include <lixel/codec/coded_map.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string_view>
#include <vector>

namespace lixel::codec {

struct DecodedMap {
    CodedHeader header;
    std::vector<float> texels;  // width * height * channels, as the encoder was given them
                                // (quantised depth within header.error_bound)
    IntegerImage values;        // what a later frame's temporal tiles read
};

class MapDecoder {
  public:
    // `max_texels`: the most texels (times channels) one image may hold; larger ones are refused
    // before any allocation.
    explicit MapDecoder(std::uint64_t max_texels = std::uint64_t{kMaxSide} * kMaxSide * 2);
    ~MapDecoder();
    MapDecoder(const MapDecoder&) = delete;
    MapDecoder& operator=(const MapDecoder&) = delete;

    // Decodes one coded map. A frame with a reference reads it from `references` (by frame id);
    // one that is absent or of another shape is an error naming coded_map.reference_id.
    Result<DecodedMap> Decode(std::string_view bytes,
                              const std::map<std::uint64_t, const IntegerImage*>& references = {});

  private:
    struct Context;
    std::unique_ptr<Context> context_;
    std::uint64_t max_texels_;
};

}  // namespace lixel::codec
