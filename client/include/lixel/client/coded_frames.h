// A client's side of coded maps (RenderRequest.encoding; docs/service.md, "Coded maps"): the
// coded images of a Render decoded, checked against the header that announced them, and the
// decoded values of the last frame held so the server can code the next frame's images as
// differences from them.
#pragma once

#include <lixel/codec/coded_map.h>
#include <lixel/codec/map_decoder.h>
#include <lixel/solver/result.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lixel::client {

class CodedFrames {
  public:
    // Names the held frames in `encoding.reference_frames` (unless the caller named some), at
    // most codec::kMaxReferenceFrames of them.
    void NameIn(v1::MapEncoding* encoding) const;

    // Decodes image `index` of `header` from its coded bytes; errors name images[index].
    Result<codec::DecodedMap> Decode(const v1::RenderHeader& header, int index,
                                     std::string_view coded);

    // The decoded values of a whole frame become the frames held (the previous ones go).
    void Hold(std::vector<codec::IntegerImage> frame);

    std::size_t held() const { return held_.size(); }

  private:
    codec::MapDecoder decoder_;
    std::vector<codec::IntegerImage> held_;
};

}  // namespace lixel::client
