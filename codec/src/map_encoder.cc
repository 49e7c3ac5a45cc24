// Encoding: values, a predictor per tile chosen by the residuals' bit length, byte planes, zstd.
#include <lixel/codec/map_encoder.h>

#include <zstd.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "tile_predictors.h"

namespace lixel::codec {

using detail::Grid;
using detail::Predict;
using detail::TileSpan;
using detail::ZigZag;

struct MapEncoder::Context {
    ZSTD_CCtx* zstd = ZSTD_createCCtx();
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

// Quantised: q = round(d (2^N - 1)) for d in [0, 1]; anything else is an exception with its
// exact bits (its q is 0, which only its neighbours' predictions read).
std::vector<std::uint32_t> Values(Content content, Codec codec, int bits, const float* texels,
                                  std::uint64_t count, std::vector<Exception>* exceptions) {
    std::vector<std::uint32_t> values(count);
    if (codec == Codec::kExact) {
        std::memcpy(values.data(), texels, count * sizeof(float));
        return values;
    }
    (void)content;
    const double steps = std::ldexp(1.0, bits) - 1.0;
    for (std::uint64_t i = 0; i < count; ++i) {
        const float d = texels[i];
        if (d >= 0.0f && d <= 1.0f) {
            values[i] = static_cast<std::uint32_t>(std::llround(static_cast<double>(d) * steps));
        } else {
            values[i] = 0;
            exceptions->push_back({static_cast<std::uint32_t>(i), std::bit_cast<std::uint32_t>(d)});
        }
    }
    return values;
}

// The cost of coding a tile with `mode`: the residuals' summed bit lengths (zstd's input is the
// byte planes, whose high planes are zero where these are short).
std::uint64_t TileCost(TileMode mode, const Grid& g, const std::uint32_t* v,
                       const std::uint32_t* ref, const TileSpan& s) {
    std::uint64_t cost = 0;
    for (std::uint32_t y = s.y0; y < s.y1; ++y) {
        for (std::uint32_t x = s.x0; x < s.x1; ++x) {
            for (int c = 0; c < g.channels; ++c) {
                const std::uint64_t at = (std::uint64_t{y} * g.width + x) * g.channels + c;
                cost += std::bit_width(ZigZag(v[at], Predict(mode, g, v, ref, x, y, c), g));
            }
        }
    }
    return cost;
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

TileMode ChooseMode(const Grid& g, const std::uint32_t* v, const std::uint32_t* ref,
                    const TileSpan& s) {
    if (ref != nullptr && SameAsReference(g, v, ref, s)) return TileMode::kCopy;
    TileMode best = TileMode::kGradient;
    std::uint64_t least = TileCost(TileMode::kGradient, g, v, ref, s);
    for (TileMode m : {TileMode::kMed, TileMode::kTemporal}) {
        if (m == TileMode::kTemporal && ref == nullptr) continue;
        if (least == 0) break;
        const std::uint64_t cost = TileCost(m, g, v, ref, s);
        if (cost < least) {
            least = cost;
            best = m;
        }
    }
    return best;
}

Result<bool> CheckOptions(Content content, std::uint32_t width, std::uint32_t height,
                          const EncodeOptions& o) {
    if (o.codec != Codec::kQuantised && o.codec != Codec::kExact) {
        return Bad("codec", "not quantised or exact");
    }
    if (o.codec == Codec::kQuantised && content != Content::kDepth) {
        return Bad("codec", "quantised codes depth only; silhouette points are exact");
    }
    if (o.codec == Codec::kQuantised && (o.bits < kMinQuantisedBits || o.bits > kMaxQuantisedBits)) {
        return Bad("bits", std::to_string(o.bits) + " is outside [16, 24]");
    }
    if (o.tile < kMinTile || o.tile > kMaxTile) {
        return Bad("tile", std::to_string(o.tile) + " is outside [8, 1024]");
    }
    if (o.zstd_level < 1 || o.zstd_level > 19) {
        return Bad("zstd_level", std::to_string(o.zstd_level) + " is outside [1, 19]");
    }
    if (o.frame_id == 0) return Bad("frame_id", "0 names no frame");
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
    h.error_bound = o.codec == Codec::kQuantised ? QuantisedErrorBound(h.bits) : 0.0;
    h.frame_id = o.frame_id;
    const Grid g = detail::GridOf(h);
    const std::uint64_t count = h.texels() * g.channels;

    std::vector<Exception> exceptions;
    std::vector<std::uint32_t> v = Values(content, o.codec, h.bits, texels, count, &exceptions);
    h.exceptions = static_cast<std::uint32_t>(exceptions.size());
    const IntegerImage* reference =
        o.reference != nullptr && o.reference->Matches(h) && o.reference->values.size() == count
            ? o.reference
            : nullptr;
    const std::uint32_t* ref = reference != nullptr ? reference->values.data() : nullptr;

    const std::uint32_t across = TilesAcross(h);
    const std::uint32_t up = TilesUp(h);
    out.tiles = std::uint64_t{across} * up;
    std::vector<TileMode> modes(out.tiles);
    std::uint64_t residuals = 0;
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const TileSpan s = detail::SpanOf(h, tx, ty);
            const TileMode m = ChooseMode(g, v.data(), ref, s);
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
    std::string raw(out.tiles + 8 * exceptions.size() + planes * residuals, '\0');
    auto* p = reinterpret_cast<unsigned char*>(raw.data());
    for (std::uint64_t t = 0; t < out.tiles; ++t) p[t] = static_cast<unsigned char>(modes[t]);
    p += out.tiles;
    for (const Exception& e : exceptions) {
        for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(e.index >> (8 * i));
        for (int i = 0; i < 4; ++i) p[4 + i] = static_cast<unsigned char>(e.bits >> (8 * i));
        p += 8;
    }
    std::uint64_t k = 0;
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const TileMode m = modes[std::uint64_t{ty} * across + tx];
            if (m == TileMode::kCopy) continue;
            const TileSpan s = detail::SpanOf(h, tx, ty);
            for (std::uint32_t y = s.y0; y < s.y1; ++y) {
                for (std::uint32_t x = s.x0; x < s.x1; ++x) {
                    for (int c = 0; c < g.channels; ++c) {
                        const std::uint64_t at = (std::uint64_t{y} * width + x) * g.channels + c;
                        const std::uint32_t z = ZigZag(v[at], Predict(m, g, v.data(), ref, x, y, c), g);
                        for (int b = 0; b < planes; ++b) {
                            p[b * residuals + k] = static_cast<unsigned char>(z >> (8 * b));
                        }
                        ++k;
                    }
                }
            }
        }
    }
    h.raw_bytes = raw.size();

    ZSTD_CCtx* z = context_->zstd;
    ZSTD_CCtx_reset(z, ZSTD_reset_session_and_parameters);
    ZSTD_CCtx_setParameter(z, ZSTD_c_compressionLevel, o.zstd_level);
    ZSTD_CCtx_setParameter(z, ZSTD_c_checksumFlag, 1);
    ZSTD_CCtx_setParameter(z, ZSTD_c_contentSizeFlag, 1);
    out.bytes.resize(kHeaderBytes + ZSTD_compressBound(raw.size()));
    const std::size_t packed = ZSTD_compress2(z, out.bytes.data() + kHeaderBytes,
                                              out.bytes.size() - kHeaderBytes, raw.data(), raw.size());
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
