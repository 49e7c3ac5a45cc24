// A coded map: one image of a Render stream (depth, second depth, corner depth or silhouette
// points) in lixel's compact format. The byte layout is specified in docs/service.md, "Coded
// maps", precisely enough for a third decoder; this header is its C++ form.
#pragma once

#include <lixel/solver/result.h>

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace lixel::codec {

// What the texels hold.
enum class Content : std::uint8_t {
    kDepth = 1,   // one float32 per texel: stored depth d (1 at the light's near end, 0 cleared)
    kPoints = 2,  // two float32 per texel (RG): silhouette points, (-1, -1) where none
};

// How a texel's value becomes the integer the predictors work on.
enum class Codec : std::uint8_t {
    // Depth only: q = round(d (2^N - 1)) for d in [0, 1], decoded as float(q / (2^N - 1)).
    // d = 0 (the clear value) and d = 1 decode exactly; any other value (outside [0, 1], NaN,
    // infinities) is an exception stored with its exact float32 bits. A tile of shift s > 0
    // holds multiples of 2^s: q = min(2^s round(d (2^N - 1) / 2^s), 2^N - 1).
    kQuantised = 1,
    // The float32 bit pattern of every channel, kept exactly (N = 32).
    kExact = 2,
};

// Per tile: how its texels are predicted (the low four bits of its tile byte; the high four are
// its shift, TileShift).
enum class TileMode : std::uint8_t {
    kGradient = 0,  // a + b - c (exact on planes, and rendered depth is planar per triangle)
    kMed = 1,       // LOCO-I's median edge detector
    kTemporal = 2,  // the reference frame's value at the same texel
    kCopy = 3,      // every texel equals the reference frame's: no residuals
};

inline constexpr std::size_t kHeaderBytes = 80;
// Version 2 added the tiles' shifts (a coarser step where a tile's own error budget allows it).
inline constexpr std::uint8_t kFormatVersion = 2;
inline constexpr int kMinQuantisedBits = 16;
inline constexpr int kMaxQuantisedBits = 24;
inline constexpr int kMinTile = 8;
inline constexpr int kMaxTile = 1024;
// The coarsest step a quantised tile may take, 2^8 of N's: N - 8 >= 8 bits remain.
inline constexpr int kMaxTileShift = 8;
inline constexpr std::uint32_t kMaxSide = 16385;  // a 16384² map's corner depth
// RenderRequest.encoding.reference_frames: the most frame ids a request names.
inline constexpr int kMaxReferenceFrames = 64;

// The most bytes a coded image of `raw_bytes` as float32 takes on the wire: the exact codec
// always fits (4 bytes a value, one a tile, zstd's bound on incompressible input, the header),
// and Render codes an image exactly where the quantised coding would not (many exceptions).
inline std::uint64_t MaxCodedBytes(std::uint64_t raw_bytes) {
    return raw_bytes + raw_bytes / 32 + 8192;
}

// The fixed header every coded map starts with (docs/service.md, "Coded maps").
struct CodedHeader {
    Content content = Content::kDepth;
    Codec codec = Codec::kQuantised;
    int bits = 24;            // N: [16, 24] quantised, 32 exact
    std::uint32_t width = 0;  // texels, [1, kMaxSide]
    std::uint32_t height = 0;
    int tile = 64;                    // tile side, texels, [kMinTile, kMaxTile]
    int max_shift = 0;                // the largest tile shift, [0, kMaxTileShift]; 0 exact
    std::uint32_t exceptions = 0;     // texels stored with exact float32 bits (quantised only)
    double error_bound = 0.0;  // max |decoded - float| over texels in [0, 1]: N's at max_shift
    std::uint64_t frame_id = 0;       // this image's id, non-zero
    std::uint64_t reference_id = 0;   // the image its temporal tiles read; 0: none (keyframe)
    std::uint64_t keyframe_id = 0;    // the keyframe its chain of references starts at
    std::uint64_t payload_bytes = 0;  // the zstd frame that follows the header
    std::uint64_t raw_bytes = 0;      // that frame's content size

    int channels() const { return content == Content::kPoints ? 2 : 1; }
    std::uint64_t texels() const { return std::uint64_t{width} * height; }
};

// The error bound of a quantised tile of N bits and shift s: half its step (2^s of N's), plus
// the float32 rounding of the decoded value (half an ulp of values below 1, 2^-25). A header
// states it at its max_shift.
double QuantisedErrorBound(int bits, int shift = 0);

// A tile's byte in the payload: its mode in the low four bits, its shift in the high four.
inline std::uint8_t TileByte(TileMode mode, int shift) {
    return static_cast<std::uint8_t>(static_cast<int>(mode) | shift << 4);
}
inline int TileModeBits(std::uint8_t byte) { return byte & 15; }
inline int TileShift(std::uint8_t byte) { return byte >> 4; }

// Bytes per residual: ceil(N / 8).
int BytePlanes(int bits);

// Tiles across and up.
std::uint32_t TilesAcross(const CodedHeader& h);
std::uint32_t TilesUp(const CodedHeader& h);

void WriteHeader(const CodedHeader& header, unsigned char out[kHeaderBytes]);
// Reads and checks the header at the start of `bytes`: magic, version, CRC-32, every field's
// range and their consistency (the bound is the one N states). Errors name the field.
Result<CodedHeader> ReadHeader(std::string_view bytes);

// An image's values as the predictors see them: N-bit integers (quantised) or float32 bits
// (exact), channels interleaved, row 0 at the bottom. A decoder keeps these for the next frame's
// temporal tiles; an encoder keeps the same, so both predict from identical values.
struct IntegerImage {
    Content content = Content::kDepth;
    Codec codec = Codec::kQuantised;
    int bits = 24;
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint64_t frame_id = 0;
    std::uint64_t keyframe_id = 0;
    std::vector<std::uint32_t> values;  // width * height * channels

    int channels() const { return content == Content::kPoints ? 2 : 1; }
    // Whether `h`'s temporal tiles may read this image.
    bool Matches(const CodedHeader& h) const {
        return content == h.content && codec == h.codec && bits == h.bits && width == h.width &&
               height == h.height;
    }
};

}  // namespace lixel::codec
