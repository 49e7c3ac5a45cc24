// Decoding, every size checked before it is used: the header (ReadHeader), the caller's texel
// budget, zstd's frame header (content size, checksum flag), then the payload's own layout.
#include <lixel/codec/map_decoder.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "tile_predictors.h"

namespace lixel::codec {

using detail::Grid;
using detail::TileSpan;
using detail::UnZigZag;

struct MapDecoder::Context {
    ZSTD_DCtx* zstd = ZSTD_createDCtx();
    // Scratch kept from image to image (the payload, the residuals in walk order), so a
    // stream's decoder allocates its buffers once.
    std::string raw;
    std::vector<std::uint32_t> residuals;
    ~Context() { ZSTD_freeDCtx(zstd); }
};

MapDecoder::MapDecoder(std::uint64_t max_texels)
    : context_(std::make_unique<Context>()), max_texels_(max_texels) {}
MapDecoder::~MapDecoder() = default;

namespace {

Error Bad(const std::string& field, const std::string& reason) {
    return Error{"coded_map." + field, reason};
}

std::uint32_t Le32(const unsigned char* p) {
    return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
           std::uint32_t{p[3]} << 24;
}

Result<const IntegerImage*> ReferenceOf(const CodedHeader& h,
                                        const std::map<std::uint64_t, const IntegerImage*>& held) {
    if (h.reference_id == 0) return static_cast<const IntegerImage*>(nullptr);
    const auto found = held.find(h.reference_id);
    if (found == held.end() || found->second == nullptr) {
        return Bad("reference_id", "frame " + std::to_string(h.reference_id) +
                                       " is not held (its keyframe is " +
                                       std::to_string(h.keyframe_id) + "): ask for a keyframe");
    }
    const IntegerImage& r = *found->second;
    if (!r.Matches(h) || r.values.size() != h.texels() * h.channels()) {
        return Bad("reference_id", "frame " + std::to_string(h.reference_id) +
                                       " is not of this image's content, codec, N and size");
    }
    // The caller's values: a frame with any beyond N bits is no decoded frame.
    std::uint32_t bits = 0;
    for (std::uint32_t value : r.values) bits |= value;
    if (h.bits < 32 && bits >> h.bits != 0) {
        return Bad("reference_id", "frame " + std::to_string(h.reference_id) +
                                       " holds values beyond N bits: not a decoded frame");
    }
    return &r;
}

// The zstd frame: one frame, its content size stated and equal to the header's, its checksum on
// (RFC 8878 §3.1.1: the magic number, then the frame header descriptor, whose bit 2 is the
// content checksum flag).
Result<bool> CheckFrame(const CodedHeader& h, std::string_view payload) {
    const auto* p = reinterpret_cast<const unsigned char*>(payload.data());
    if (payload.size() < 5 || Le32(p) != 0xFD2FB528u) {
        return Bad("payload", "not a zstd frame");
    }
    if ((p[4] & 0x04u) == 0) return Bad("payload", "its zstd frame carries no checksum");
    const unsigned long long size = ZSTD_getFrameContentSize(payload.data(), payload.size());
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size != h.raw_bytes) {
        return Bad("payload", "its zstd frame does not state the header's raw_bytes");
    }
    const std::size_t frame = ZSTD_findFrameCompressedSize(payload.data(), payload.size());
    if (ZSTD_isError(frame) || frame != payload.size()) {
        return Bad("payload", "not exactly one zstd frame (truncated or followed by bytes)");
    }
    return true;
}

// The residuals in walk order, joined from their byte planes (one plane at a time: a loop the
// compiler vectorises).
struct ResidualReader {
    const std::uint32_t* next;  // the next residual to read
    std::uint32_t bits = 0;  // each residual is N bits: larger ones would give a map two codings

    ResidualReader(const unsigned char* planes_base, std::uint64_t count, int planes,
                   std::vector<std::uint32_t>& scratch) {
        if (scratch.size() < count) scratch.resize(count);
        std::uint32_t* out = scratch.data();
        next = out;
        for (std::uint64_t i = 0; i < count; ++i) out[i] = planes_base[i];
        for (int b = 1; b < planes; ++b) {
            const unsigned char* plane = planes_base + b * count;
            const int shift = 8 * b;
            for (std::uint64_t i = 0; i < count; ++i) out[i] |= std::uint32_t{plane[i]} << shift;
        }
        // OR of every residual: vectorises where a max (pmaxud, SSE4.1) would not.
        for (std::uint64_t i = 0; i < count; ++i) bits |= out[i];
    }
    std::uint32_t Next() { return *next++; }
};

// Row y of a tile: each value from its residual and prediction, with texels outside the image
// read as 0 (the format's edge rule for both spatial predictors). The left and below-left
// neighbours are carried in registers from texel to texel: reading back the value just stored
// would put a store-to-load round trip on the chain every value waits for.
template <TileMode kMode, int kChannels>
void DecodeRow(const Grid& g, std::uint32_t* v, const std::uint32_t* ref,
               const std::uint32_t* zeros, const TileSpan& s, std::uint32_t y,
               ResidualReader& residual) {
    const std::uint64_t row = std::uint64_t{g.width} * kChannels;
    std::uint32_t* cur = v + y * row;
    const std::uint32_t* below = y > 0 ? cur - row : zeros;
    const std::uint64_t begin = std::uint64_t{s.x0} * kChannels;
    const std::uint64_t end = std::uint64_t{s.x1} * kChannels;
    if constexpr (kMode == TileMode::kTemporal) {
        const std::uint32_t* prior = ref + y * row;
        for (std::uint64_t i = begin; i < end; ++i) cur[i] = UnZigZag(residual.Next(), prior[i], g);
        return;
    }
    std::uint32_t a[kChannels];
    std::uint32_t d[kChannels];
    for (int c = 0; c < kChannels; ++c) {
        a[c] = s.x0 > 0 ? cur[begin - kChannels + c] : 0;
        d[c] = s.x0 > 0 ? below[begin - kChannels + c] : 0;
    }
    for (std::uint64_t i = begin; i < end; i += kChannels) {
        for (int c = 0; c < kChannels; ++c) {
            const std::uint32_t b = below[i + c];
            const std::uint32_t prediction = kMode == TileMode::kMed
                                                 ? detail::Med(a[c], b, d[c], g.mask)
                                                 : detail::Gradient(a[c], b, d[c], g.mask);
            const std::uint32_t value = UnZigZag(residual.Next(), prediction, g);
            cur[i + c] = value;
            a[c] = value;
            d[c] = b;
        }
    }
}

// Row y of a tile of shift s > 0 (depth: one channel): each c from its residual and the
// prediction from its neighbours' Coarse values, stored as Fine(c). Returns whether some c
// passed CoarseLimit (the caller refuses the map). The row below (or the reference's row) is
// coarsened first and the c's are made fine after, each in a loop of its own that vectorises,
// so that the chain each value waits for is the unshifted row's.
// `residuals`: the row's n, in walk order. (Not the ResidualReader: a reference to it passed to
// a call not inlined would keep its position in memory in every row's loop.)
template <TileMode kMode>
bool DecodeShiftedRow(const Grid& g, std::uint32_t* v, const std::uint32_t* ref,
                      const std::uint32_t* zeros, const TileSpan& s, std::uint32_t y, int shift,
                      const std::uint32_t* residuals) {
    using detail::Coarse;
    thread_local std::vector<std::uint32_t> rows;
    const std::uint64_t n = s.x1 - s.x0;
    if (rows.size() < 2 * (n + 1)) rows.resize(2 * (n + 1));
    std::uint32_t* known = rows.data();  // entry 0: the texel left of x0, below or in the row
    std::uint32_t* c = known + n + 1;
    const std::uint64_t at = std::uint64_t{y} * g.width;
    std::uint32_t* cur = v + at;
    const std::uint32_t* below = kMode == TileMode::kTemporal ? ref + at
                                 : y > 0                      ? cur - g.width
                                                              : zeros;
    detail::CoarsenRow(below, s.x0, n, shift, known);
    if constexpr (kMode == TileMode::kTemporal) {
        for (std::uint64_t i = 0; i < n; ++i) c[i] = UnZigZag(residuals[i], known[i + 1], g);
    } else {
        // The left neighbour's c is carried (inside the tile Coarse gives it back, or the map
        // is refused); the tile's first column reads its left neighbour coarsened.
        std::uint32_t a = s.x0 > 0 ? Coarse(cur[s.x0 - 1], shift) : 0;
        for (std::uint64_t i = 0; i < n; ++i) {
            const std::uint32_t prediction =
                kMode == TileMode::kMed ? detail::Med(a, known[i + 1], known[i], g.mask)
                                        : detail::Gradient(a, known[i + 1], known[i], g.mask);
            a = UnZigZag(residuals[i], prediction, g);
            c[i] = a;
        }
    }
    const auto mask = static_cast<std::uint32_t>(g.mask);
    const std::uint32_t limit = detail::CoarseLimit(g.bits, shift);
    // Fine(c) for c up to the limit (past it the map is refused, whatever the value), in signed
    // 32-bit arithmetic, which SSE2 vectorises (its unsigned min and compares it lacks): c <=
    // 2^(N - s) puts c 2^s at most 2^N. The row is addressed from a local pointer: a store
    // through a uint32 pointer could change the span's own uint32 x0, which would stop the
    // loop's vectorisation.
    std::uint32_t* to = cur + s.x0;
    const auto most = static_cast<std::int32_t>(limit);
    const auto top = static_cast<std::int32_t>(mask);
    std::int32_t over = 0;
    for (std::uint64_t i = 0; i < n; ++i) {
        const auto k = static_cast<std::int32_t>(c[i]);  // below 2^N: modulo 2^N
        over |= k > most ? 1 : 0;
        const std::int32_t q = (k < most ? k : most) << shift;
        to[i] = static_cast<std::uint32_t>(q < top ? q : top);
    }
    return over != 0;
}

// A tile of shift s > 0, row by row; whether some c passed CoarseLimit. Kept out of Decode (one
// call a tile), so that Decode's own loops, the unshifted tiles', compile as they did without
// shifts.
[[gnu::noinline]] bool DecodeShiftedTile(const Grid& g, std::uint32_t* v, const std::uint32_t* ref,
                                         const std::uint32_t* zeros, const TileSpan& s,
                                         TileMode mode, int shift, const std::uint32_t* residuals) {
    bool over = false;
    const std::uint64_t n = s.x1 - s.x0;
    for (std::uint32_t y = s.y0; y < s.y1; ++y, residuals += n) {
        switch (mode) {
            case TileMode::kTemporal:
                over |=
                    DecodeShiftedRow<TileMode::kTemporal>(g, v, ref, zeros, s, y, shift, residuals);
                break;
            case TileMode::kMed:
                over |= DecodeShiftedRow<TileMode::kMed>(g, v, ref, zeros, s, y, shift, residuals);
                break;
            default:
                over |=
                    DecodeShiftedRow<TileMode::kGradient>(g, v, ref, zeros, s, y, shift, residuals);
        }
    }
    return over;
}

template <TileMode kMode>
void DecodeRow(const Grid& g, std::uint32_t* v, const std::uint32_t* ref,
               const std::uint32_t* zeros, const TileSpan& s, std::uint32_t y,
               ResidualReader& residual) {
    if (g.channels == 1) {
        DecodeRow<kMode, 1>(g, v, ref, zeros, s, y, residual);
    } else {
        DecodeRow<kMode, 2>(g, v, ref, zeros, s, y, residual);
    }
}

// float32(q / (2^N - 1)), computed in double. Not inlined: in Decode, beside the shifted tiles'
// decoding, GCC 12 no longer vectorised the loop (twice its instructions, a tenth of a room
// image's decoding, callgrind).
[[gnu::noinline]] void ToDepth(const std::uint32_t* __restrict values, std::uint64_t count,
                               double steps, float* __restrict texels) {
    for (std::uint64_t i = 0; i < count; ++i) {
        texels[i] = static_cast<float>(static_cast<double>(values[i]) / steps);
    }
}

}  // namespace

Result<DecodedMap> MapDecoder::Decode(
    std::string_view bytes, const std::map<std::uint64_t, const IntegerImage*>& references) {
    auto header = ReadHeader(bytes);
    if (!header) return header.error();
    const CodedHeader& h = *header;
    const std::uint64_t count = h.texels() * h.channels();
    if (count > max_texels_) {
        return Bad("width", std::to_string(h.width) + " x " + std::to_string(h.height) + " x " +
                                std::to_string(h.channels()) + " values, over the decoder's " +
                                std::to_string(max_texels_));
    }
    auto reference = ReferenceOf(h, references);
    if (!reference) return reference.error();
    const std::string_view payload = bytes.substr(kHeaderBytes);
    if (auto ok = CheckFrame(h, payload); !ok) return ok.error();

    std::string& raw = context_->raw;
    raw.resize(h.raw_bytes);
    const std::size_t got =
        ZSTD_decompressDCtx(context_->zstd, raw.data(), raw.size(), payload.data(), payload.size());
    if (ZSTD_isError(got)) return Bad("payload", std::string("zstd: ") + ZSTD_getErrorName(got));
    if (got != raw.size()) return Bad("payload", "decompressed size is not raw_bytes");

    const std::uint32_t across = TilesAcross(h);
    const std::uint32_t up = TilesUp(h);
    const std::uint64_t tiles = std::uint64_t{across} * up;
    const auto* p = reinterpret_cast<const unsigned char*>(raw.data());
    const std::uint32_t* ref = *reference != nullptr ? (*reference)->values.data() : nullptr;
    std::uint64_t residuals = 0;
    bool temporal = false;
    int largest_shift = 0;
    for (std::uint64_t t = 0; t < tiles; ++t) {
        largest_shift = std::max(largest_shift, TileShift(p[t]));
        if (TileModeBits(p[t]) > 3) {
            return Bad("tile_modes", "tile " + std::to_string(t) + " has mode " +
                                         std::to_string(TileModeBits(p[t])));
        }
        if (TileShift(p[t]) > h.max_shift) {
            return Bad("tile_modes", "tile " + std::to_string(t) + " has shift " +
                                         std::to_string(TileShift(p[t])) +
                                         ", past the header's max_shift " +
                                         std::to_string(h.max_shift));
        }
        const auto m = static_cast<TileMode>(TileModeBits(p[t]));
        if (m == TileMode::kTemporal || m == TileMode::kCopy) {
            if (ref == nullptr) {
                return Bad("tile_modes", "tile " + std::to_string(t) +
                                             " reads a reference frame, and none is named");
            }
            temporal = true;
        }
        if (m != TileMode::kCopy) {
            const TileSpan s = detail::SpanOf(h, static_cast<std::uint32_t>(t % across),
                                              static_cast<std::uint32_t>(t / across));
            residuals += std::uint64_t(s.x1 - s.x0) * (s.y1 - s.y0) * h.channels();
        }
    }
    // One map, one coding: the header states the largest shift its tiles take, not more.
    if (largest_shift != h.max_shift) {
        return Bad("max_shift", std::to_string(h.max_shift) + ", but the largest tile shift is " +
                                    std::to_string(largest_shift));
    }
    if (!temporal && h.reference_id != 0) {
        return Bad("reference_id", "named, but no tile reads it");
    }
    const int planes = BytePlanes(h.bits);
    if (h.raw_bytes != tiles + 8ull * h.exceptions + planes * residuals) {
        return Bad("raw_bytes",
                   std::to_string(h.raw_bytes) + " is not what its tiles and " +
                       "exceptions need (" +
                       std::to_string(tiles + 8ull * h.exceptions + planes * residuals) + ")");
    }

    DecodedMap out;
    out.header = h;
    IntegerImage& values = out.values;
    values.content = h.content;
    values.codec = h.codec;
    values.bits = h.bits;
    values.width = h.width;
    values.height = h.height;
    values.frame_id = h.frame_id;
    values.keyframe_id = h.keyframe_id;
    values.values.assign(count, 0);
    std::uint32_t* v = values.values.data();
    const Grid g = detail::GridOf(h);
    const unsigned char* exceptions = p + tiles;
    const unsigned char* z = exceptions + 8ull * h.exceptions;
    const std::vector<std::uint32_t> zeros(std::uint64_t{h.width} * g.channels, 0);
    ResidualReader residual(z, residuals, planes, context_->residuals);
    if (residual.bits > g.mask) return Bad("payload", "a residual beyond N bits");
    bool over = false;
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const std::uint8_t byte = p[std::uint64_t{ty} * across + tx];
            const auto m = static_cast<TileMode>(TileModeBits(byte));
            const int shift = TileShift(byte);
            const TileSpan s = detail::SpanOf(h, tx, ty);
            if (shift > 0 && m != TileMode::kCopy) {
                over |= DecodeShiftedTile(g, v, ref, zeros.data(), s, m, shift, residual.next);
                residual.next += std::uint64_t(s.x1 - s.x0) * (s.y1 - s.y0);
                continue;
            }
            for (std::uint32_t y = s.y0; y < s.y1; ++y) {
                switch (m) {
                    case TileMode::kGradient:
                        DecodeRow<TileMode::kGradient>(g, v, ref, zeros.data(), s, y, residual);
                        break;
                    case TileMode::kMed:
                        DecodeRow<TileMode::kMed>(g, v, ref, zeros.data(), s, y, residual);
                        break;
                    case TileMode::kTemporal:
                        DecodeRow<TileMode::kTemporal>(g, v, ref, zeros.data(), s, y, residual);
                        break;
                    case TileMode::kCopy: {
                        const std::uint64_t at = (std::uint64_t{y} * h.width + s.x0) * g.channels;
                        std::memcpy(v + at, ref + at,
                                    std::size_t(s.x1 - s.x0) * g.channels * sizeof(std::uint32_t));
                        break;
                    }
                }
            }
        }
    }

    if (over) {
        return Bad("payload", "a shifted tile's value past 2^(N - shift): not a coded map");
    }

    out.texels.resize(count);
    if (h.codec == Codec::kExact) {
        std::memcpy(out.texels.data(), v, count * sizeof(float));
        return out;
    }
    ToDepth(v, count, std::ldexp(1.0, h.bits) - 1.0, out.texels.data());
    std::uint64_t previous = 0;
    for (std::uint32_t e = 0; e < h.exceptions; ++e) {
        const std::uint32_t index = Le32(exceptions + 8ull * e);
        if (index >= count || (e > 0 && index <= previous)) {
            return Bad("exceptions", "exception " + std::to_string(e) + " at texel " +
                                         std::to_string(index) + " is out of range or order");
        }
        previous = index;
        if (v[index] != 0) {
            return Bad("exceptions", "exception " + std::to_string(e) + "'s texel holds an " +
                                         "integer other than 0");
        }
        out.texels[index] = std::bit_cast<float>(Le32(exceptions + 8ull * e + 4));
    }
    return out;
}

}  // namespace lixel::codec
