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
    // infinities) is an exception stored with its exact float32 bits.
    kQuantised = 1,
    // The float32 bit pattern of every channel, kept exactly (N = 32).
    kExact = 2,
};

// Per tile: how its texels are predicted.
enum class TileMode : std::uint8_t {
    kGradient = 0,  // a + b - c (exact on planes, and rendered depth is planar per triangle)
    kMed = 1,       // LOCO-I's median edge detector
    kTemporal = 2,  // the reference frame's value at the same texel
    kCopy = 3,      // every texel equals the reference frame's: no residuals
};

inline constexpr std::size_t kHeaderBytes = 80;
inline constexpr std::uint8_t kFormatVersion = 1;
inline constexpr int kMinQuantisedBits = 16;
inline constexpr int kMaxQuantisedBits = 24;
inline constexpr int kMinTile = 8;
inline constexpr int kMaxTile = 1024;
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
    std::uint32_t exceptions = 0;     // texels stored with exact float32 bits (quantised only)
    double error_bound = 0.0;         // max |decoded - float| over texels in [0, 1]; 0 exact
    std::uint64_t frame_id = 0;       // this image's id, non-zero
    std::uint64_t reference_id = 0;   // the image its temporal tiles read; 0: none (keyframe)
    std::uint64_t keyframe_id = 0;    // the keyframe its chain of references starts at
    std::uint64_t payload_bytes = 0;  // the zstd frame that follows the header
    std::uint64_t raw_bytes = 0;      // that frame's content size

    int channels() const { return content == Content::kPoints ? 2 : 1; }
    std::uint64_t texels() const { return std::uint64_t{width} * height; }
};

// The error bound a quantised map states for N bits: half a quantisation step, plus the float32
// rounding of the decoded value (half an ulp of values below 1, 2^-25).
double QuantisedErrorBound(int bits);

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
