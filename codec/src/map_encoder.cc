// Encoding: values, a predictor per tile chosen by the residuals' bit length, byte planes, zstd.
#include <lixel/codec/map_encoder.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "tile_predictors.h"

namespace lixel::codec {

using detail::Grid;
using detail::TileSpan;
using detail::ZigZag;

struct MapEncoder::Context {
    ZSTD_CCtx* zstd = ZSTD_createCCtx();
    // Scratch kept from image to image, so a stream's encoder allocates (and the kernel faults
    // in) its buffers once: the residuals in walk order, the payload before zstd.
    std::vector<std::uint32_t> walk;
    std::string raw;
    ~Context() { ZSTD_freeCCtx(zstd); }
};

MapEncoder::MapEncoder() : context_(std::make_unique<Context>()) {}
MapEncoder::~MapEncoder() = default;

namespace {

Error Bad(const std::string& field, const std::string& reason) {
    return Error{"codec." + field, reason};
}

struct Exception {
    std::uint32_t index;
    std::uint32_t bits;
};

// Quantised: q = round(d (2^N - 1)) for d in [0, 1], in a tile of shift s > 0 q = Fine(c) with
// c = round(d (2^N - 1) / 2^s) (from d, not from the finer q, whose own rounding would add to
// the tile's error); anything else is an exception with its exact bits (its q is 0, which only
// its neighbours' predictions read). `shifts`: per tile of `tile`, or empty for all 0.
std::vector<std::uint32_t> Values(Codec codec, int bits, const float* texels, std::uint32_t width,
                                  std::uint32_t height, int channels, int tile,
                                  const std::vector<std::uint8_t>& shifts,
                                  std::vector<Exception>* exceptions) {
    const std::uint64_t count = std::uint64_t{width} * height * channels;
    std::vector<std::uint32_t> values(count);
    if (codec == Codec::kExact) {
        std::memcpy(values.data(), texels, count * sizeof(float));
        return values;
    }
    const double steps = std::ldexp(1.0, bits) - 1.0;
    const auto exception = [&](std::uint64_t i, float d) {
        values[i] = 0;
        exceptions->push_back({static_cast<std::uint32_t>(i), std::bit_cast<std::uint32_t>(d)});
    };
    if (shifts.empty()) {  // one loop, N's step everywhere
        for (std::uint64_t i = 0; i < count; ++i) {
            const float d = texels[i];
            if (d >= 0.0f && d <= 1.0f) {
                // d >= 0: adding a half and truncating rounds half away from zero, as llround.
                values[i] = static_cast<std::uint32_t>(static_cast<double>(d) * steps + 0.5);
            } else {
                exception(i, d);
            }
        }
        return values;
    }
    const auto mask = static_cast<std::uint32_t>(steps);
    const auto t = static_cast<std::uint32_t>(tile);
    const std::uint32_t across = (width + t - 1) / t;
    for (std::uint32_t y = 0; y < height; ++y) {
        for (std::uint32_t x0 = 0; x0 < width; x0 += t) {
            const int shift = shifts[(y / t) * across + x0 / t];
            const double scale = std::ldexp(steps, -shift);
            const std::uint64_t end = std::uint64_t{y} * width + std::min(width, x0 + t);
            for (std::uint64_t i = std::uint64_t{y} * width + x0; i < end; ++i) {
                const float d = texels[i];
                if (d >= 0.0f && d <= 1.0f) {
                    const auto c = static_cast<std::uint32_t>(static_cast<double>(d) * scale + 0.5);
                    values[i] = detail::Fine(c, shift, mask);
                } else {
                    exception(i, d);
                }
            }
        }
    }
    return values;
}

// Residuals of texels [x0, x1) of row y under `kMode`, zig-zagged, into `out` when given; returns
// their summed bit lengths (zstd's input is the byte planes, whose high planes are zero where
// the residuals are short). Texels outside the image read as 0, which is the format's edge rule
// for both spatial predictors.
template <TileMode kMode, int kChannels>
std::uint64_t RowResiduals(const Grid& g, const std::uint32_t* v, const std::uint32_t* ref,
                           const std::uint32_t* zeros, std::uint32_t x0, std::uint32_t x1,
                           std::uint32_t y, std::uint32_t* out) {
    const std::uint64_t row = std::uint64_t{g.width} * kChannels;
    const std::uint32_t* cur = v + y * row;
    const std::uint32_t* below = y > 0 ? cur - row : zeros;
    const std::uint32_t* prior = ref != nullptr ? ref + y * row : nullptr;
    std::uint64_t bits = 0;
    for (std::uint64_t i = std::uint64_t{x0} * kChannels; i < std::uint64_t{x1} * kChannels; ++i) {
        std::uint32_t prediction;
        if constexpr (kMode == TileMode::kTemporal) {
            prediction = prior[i];
        } else {
            const bool left = i >= kChannels;
            const std::uint32_t a = left ? cur[i - kChannels] : 0;
            const std::uint32_t d = left ? below[i - kChannels] : 0;
            prediction = kMode == TileMode::kMed ? detail::Med(a, below[i], d, g.mask)
                                                 : detail::Gradient(a, below[i], d, g.mask);
        }
        const std::uint32_t z = ZigZag(cur[i], prediction, g);
        if (out != nullptr) *out++ = z;
        bits += static_cast<std::uint64_t>(std::bit_width(z));
    }
    return bits;
}

// The same for a tile of shift s > 0 (depth: one channel): the row, the row below and the
// reference's row read as their Coarse values into per-thread rows whose entry 0 is the texel
// left of x0 (0 at the image's edge, the format's edge rule), so that the residuals' loop has no
// branch and vectorises as RowResiduals' does.
template <TileMode kMode>
std::uint64_t ShiftedRowResiduals(const Grid& g, const std::uint32_t* v, const std::uint32_t* ref,
                                  const std::uint32_t* zeros, std::uint32_t x0, std::uint32_t x1,
                                  std::uint32_t y, int shift, std::uint32_t* out) {
    thread_local std::vector<std::uint32_t> rows;
    const std::uint64_t n = x1 - x0;
    if (rows.size() < 3 * (n + 1)) rows.resize(3 * (n + 1));
    std::uint32_t* cur = rows.data();
    std::uint32_t* below = cur + n + 1;
    std::uint32_t* prior = below + n + 1;
    const std::uint64_t at = std::uint64_t{y} * g.width;
    detail::CoarsenRow(v + at, x0, n, shift, cur);
    if constexpr (kMode == TileMode::kTemporal) {
        detail::CoarsenRow(ref + at, x0, n, shift, prior);
    } else {
        detail::CoarsenRow(y > 0 ? v + at - g.width : zeros, x0, n, shift, below);
    }
    std::uint64_t bits = 0;
    for (std::uint64_t i = 1; i <= n; ++i) {
        std::uint32_t prediction;
        if constexpr (kMode == TileMode::kTemporal) {
            prediction = prior[i];
        } else {
            prediction = kMode == TileMode::kMed
                             ? detail::Med(cur[i - 1], below[i], below[i - 1], g.mask)
                             : detail::Gradient(cur[i - 1], below[i], below[i - 1], g.mask);
        }
        const std::uint32_t z = ZigZag(cur[i], prediction, g);
        if (out != nullptr) *out++ = z;
        bits += static_cast<std::uint64_t>(std::bit_width(z));
    }
    return bits;
}

template <TileMode kMode>
std::uint64_t RowResiduals(const Grid& g, const std::uint32_t* v, const std::uint32_t* ref,
                           const std::uint32_t* zeros, std::uint32_t x0, std::uint32_t x1,
                           std::uint32_t y, int shift, std::uint32_t* out) {
    if (shift > 0) return ShiftedRowResiduals<kMode>(g, v, ref, zeros, x0, x1, y, shift, out);
    return g.channels == 1 ? RowResiduals<kMode, 1>(g, v, ref, zeros, x0, x1, y, out)
                           : RowResiduals<kMode, 2>(g, v, ref, zeros, x0, x1, y, out);
}

std::uint64_t RowResiduals(TileMode mode, const Grid& g, const std::uint32_t* v,
                           const std::uint32_t* ref, const std::uint32_t* zeros, std::uint32_t x0,
                           std::uint32_t x1, std::uint32_t y, int shift, std::uint32_t* out) {
    switch (mode) {
        case TileMode::kMed:
            return RowResiduals<TileMode::kMed>(g, v, ref, zeros, x0, x1, y, shift, out);
        case TileMode::kTemporal:
            return RowResiduals<TileMode::kTemporal>(g, v, ref, zeros, x0, x1, y, shift, out);
        default:
            return RowResiduals<TileMode::kGradient>(g, v, ref, zeros, x0, x1, y, shift, out);
    }
}

bool SameAsReference(const Grid& g, const std::uint32_t* v, const std::uint32_t* ref,
                     const TileSpan& s) {
    const std::size_t n = std::size_t(s.x1 - s.x0) * g.channels;
    for (std::uint32_t y = s.y0; y < s.y1; ++y) {
        const std::uint64_t at = (std::uint64_t{y} * g.width + s.x0) * g.channels;
        if (std::memcmp(v + at, ref + at, n * sizeof(std::uint32_t)) != 0) return false;
    }
    return true;
}

// The mode the choice estimates from every kCostRowStep-th row of a tile: the choice only steers
// the size (each residual is then taken with the chosen predictor), and a tile's rows are alike.
constexpr std::uint32_t kCostRowStep = 4;

// A tile's mode: a copy where every value equals the reference's, else the predictor whose
// residuals have the fewest summed bits on the sampled rows (the gradient on ties).
TileMode ChooseMode(const Grid& g, const std::uint32_t* v, const std::uint32_t* ref,
                    const std::uint32_t* zeros, const TileSpan& s, int shift) {
    if (ref != nullptr && SameAsReference(g, v, ref, s)) return TileMode::kCopy;
    TileMode best = TileMode::kGradient;
    std::uint64_t least = ~std::uint64_t{0};
    for (TileMode m : {TileMode::kGradient, TileMode::kMed, TileMode::kTemporal}) {
        if (m == TileMode::kTemporal && ref == nullptr) continue;
        std::uint64_t cost = 0;
        for (std::uint32_t y = s.y0; y < s.y1 && cost < least; y += kCostRowStep) {
            cost += RowResiduals(m, g, v, ref, zeros, s.x0, s.x1, y, shift, nullptr);
        }
        if (cost < least) {
            least = cost;
            best = m;
        }
    }
    return best;
}

// Byte `kPlane` of every residual (a constant shift: a loop the compiler vectorises).
template <int kPlane>
void SplitPlane(const std::uint32_t* z, std::uint64_t count, unsigned char* plane) {
    for (std::uint64_t i = 0; i < count; ++i)
        plane[i] = static_cast<unsigned char>(z[i] >> (8 * kPlane));
}

Result<bool> CheckOptions(Content content, std::uint32_t width, std::uint32_t height,
                          const EncodeOptions& o) {
    if (o.codec != Codec::kQuantised && o.codec != Codec::kExact) {
        return Bad("codec", "not quantised or exact");
    }
    if (o.codec == Codec::kQuantised && content != Content::kDepth) {
        return Bad("codec", "quantised codes depth only; silhouette points are exact");
    }
    if (o.codec == Codec::kQuantised &&
        (o.bits < kMinQuantisedBits || o.bits > kMaxQuantisedBits)) {
        return Bad("bits", std::to_string(o.bits) + " is outside [16, 24]");
    }
    if (o.tile < kMinTile || o.tile > kMaxTile) {
        return Bad("tile", std::to_string(o.tile) + " is outside [8, 1024]");
    }
    if (o.zstd_level < 1 || o.zstd_level > 19) {
        return Bad("zstd_level", std::to_string(o.zstd_level) + " is outside [1, 19]");
    }
    if (o.frame_id == 0) return Bad("frame_id", "0 names no frame");
    if (!o.tile_shifts.empty()) {
        const std::uint64_t tiles = ((std::uint64_t{width} + o.tile - 1) / o.tile) *
                                    ((std::uint64_t{height} + o.tile - 1) / o.tile);
        if (o.codec != Codec::kQuantised) {
            return Bad("tile_shifts", "only a quantised image's tiles take a shift");
        }
        if (o.tile_shifts.size() != tiles) {
            return Bad("tile_shifts", std::to_string(o.tile_shifts.size()) + " shifts for " +
                                          std::to_string(tiles) + " tiles");
        }
        for (const std::uint8_t shift : o.tile_shifts) {
            if (shift > kMaxTileShift) {
                return Bad("tile_shifts", std::to_string(shift) + " is outside [0, 8]");
            }
        }
    }
    if (width < 1 || width > kMaxSide || height < 1 || height > kMaxSide) {
        return Bad("size", std::to_string(width) + " x " + std::to_string(height) +
                               " is outside [1, 16385]²");
    }
    return true;
}

}  // namespace

Result<EncodedMap> MapEncoder::Encode(Content content, const float* texels, std::uint32_t width,
                                      std::uint32_t height, const EncodeOptions& o) {
    if (auto ok = CheckOptions(content, width, height, o); !ok) return ok.error();
    EncodedMap out;
    CodedHeader& h = out.header;
    h.content = content;
    h.codec = o.codec;
    h.bits = o.codec == Codec::kExact ? 32 : o.bits;
    h.width = width;
    h.height = height;
    h.tile = o.tile;
    h.frame_id = o.frame_id;
    const Grid g = detail::GridOf(h);
    const std::uint64_t count = h.texels() * g.channels;

    std::vector<Exception> exceptions;
    std::vector<std::uint32_t> v = Values(o.codec, h.bits, texels, width, height, g.channels,
                                          h.tile, o.tile_shifts, &exceptions);
    h.exceptions = static_cast<std::uint32_t>(exceptions.size());
    const std::uint32_t across = TilesAcross(h);
    const std::uint32_t up = TilesUp(h);
    const auto shift_of = [&](std::uint32_t tx, std::uint32_t ty) {
        return o.tile_shifts.empty() ? 0 : int{o.tile_shifts[std::uint64_t{ty} * across + tx]};
    };
    for (const std::uint8_t shift : o.tile_shifts) h.max_shift = std::max(h.max_shift, int{shift});
    if (h.codec == Codec::kQuantised) h.error_bound = QuantisedErrorBound(h.bits, h.max_shift);
    const IntegerImage* reference =
        o.reference != nullptr && o.reference->Matches(h) && o.reference->values.size() == count
            ? o.reference
            : nullptr;
    const std::uint32_t* ref = reference != nullptr ? reference->values.data() : nullptr;

    out.tiles = std::uint64_t{across} * up;
    const std::vector<std::uint32_t> zeros(std::uint64_t{width} * g.channels, 0);
    std::vector<TileMode> modes(out.tiles);
    std::uint64_t residuals = 0;
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const TileSpan s = detail::SpanOf(h, tx, ty);
            const TileMode m = ChooseMode(g, v.data(), ref, zeros.data(), s, shift_of(tx, ty));
            modes[std::uint64_t{ty} * across + tx] = m;
            if (m == TileMode::kTemporal || m == TileMode::kCopy) ++out.temporal_tiles;
            if (m != TileMode::kCopy) {
                residuals += std::uint64_t(s.x1 - s.x0) * (s.y1 - s.y0) * g.channels;
            }
        }
    }
    if (out.temporal_tiles > 0) {
        h.reference_id = reference->frame_id;
        h.keyframe_id = reference->keyframe_id;
    } else {
        h.keyframe_id = h.frame_id;
    }

    const int planes = BytePlanes(h.bits);
    std::string& raw = context_->raw;
    raw.resize(out.tiles + 8 * exceptions.size() + planes * residuals);  // every byte is written
    auto* p = reinterpret_cast<unsigned char*>(raw.data());
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const std::uint64_t t = std::uint64_t{ty} * across + tx;
            p[t] = TileByte(modes[t], shift_of(tx, ty));
        }
    }
    p += out.tiles;
    for (const Exception& e : exceptions) {
        for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(e.index >> (8 * i));
        for (int i = 0; i < 4; ++i) p[4 + i] = static_cast<unsigned char>(e.bits >> (8 * i));
        p += 8;
    }
    // The residuals in walk order, then split into byte planes.
    std::vector<std::uint32_t>& walk = context_->walk;
    if (walk.size() < residuals) walk.resize(residuals);
    std::uint64_t k = 0;
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const TileMode m = modes[std::uint64_t{ty} * across + tx];
            if (m == TileMode::kCopy) continue;
            const TileSpan s = detail::SpanOf(h, tx, ty);
            for (std::uint32_t y = s.y0; y < s.y1; ++y) {
                RowResiduals(m, g, v.data(), ref, zeros.data(), s.x0, s.x1, y, shift_of(tx, ty),
                             walk.data() + k);
                k += std::uint64_t(s.x1 - s.x0) * g.channels;
            }
        }
    }
    SplitPlane<0>(walk.data(), residuals, p);
    if (planes > 1) SplitPlane<1>(walk.data(), residuals, p + residuals);
    if (planes > 2) SplitPlane<2>(walk.data(), residuals, p + 2 * residuals);
    if (planes > 3) SplitPlane<3>(walk.data(), residuals, p + 3 * residuals);
    h.raw_bytes = raw.size();

    ZSTD_CCtx* z = context_->zstd;
    ZSTD_CCtx_reset(z, ZSTD_reset_session_and_parameters);
    ZSTD_CCtx_setParameter(z, ZSTD_c_compressionLevel, o.zstd_level);
    ZSTD_CCtx_setParameter(z, ZSTD_c_checksumFlag, 1);
    ZSTD_CCtx_setParameter(z, ZSTD_c_contentSizeFlag, 1);
    out.bytes.resize(kHeaderBytes + ZSTD_compressBound(raw.size()));
    const std::size_t packed =
        ZSTD_compress2(z, out.bytes.data() + kHeaderBytes, out.bytes.size() - kHeaderBytes,
                       raw.data(), raw.size());
    if (ZSTD_isError(packed)) return Bad("zstd", ZSTD_getErrorName(packed));
    out.bytes.resize(kHeaderBytes + packed);
    h.payload_bytes = packed;
    WriteHeader(h, reinterpret_cast<unsigned char*>(out.bytes.data()));

    out.decoded.content = content;
    out.decoded.codec = h.codec;
    out.decoded.bits = h.bits;
    out.decoded.width = width;
    out.decoded.height = height;
    out.decoded.frame_id = h.frame_id;
    out.decoded.keyframe_id = h.keyframe_id;
    out.decoded.values = std::move(v);
    return out;
}

}  // namespace lixel::codec
