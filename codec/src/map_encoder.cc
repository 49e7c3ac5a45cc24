// Encoding: values, a predictor per tile chosen by the residuals' bit length, byte planes, zstd.
#include <lixel/codec/map_encoder.h>

#include <zstd.h>

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
    // in) its buffers once: the predictors' residuals, the walk, the payload before zstd.
    std::vector<std::uint32_t> residuals[3];
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
            // d >= 0: adding a half and truncating rounds half away from zero, as llround.
            values[i] = static_cast<std::uint32_t>(static_cast<double>(d) * steps + 0.5);
        } else {
            values[i] = 0;
            exceptions->push_back({static_cast<std::uint32_t>(i), std::bit_cast<std::uint32_t>(d)});
        }
    }
    return values;
}

// Every value's residual under the spatial predictors (and the reference, when there is one),
// in one pass, with each tile's cost under each: the residuals' summed bit lengths (zstd's input
// is the byte planes, whose high planes are zero where these are short). Texels outside the
// image read as 0, which is the format's edge rule (the bottom row predicts from its left
// neighbour, the left column from below, texel (0, 0) from 0) for both predictors.
struct Residuals {
    std::uint32_t* z[3] = {nullptr, nullptr, nullptr};  // by TileMode: gradient, MED, temporal
    std::vector<std::uint64_t> cost[3];      // per tile
    std::vector<unsigned char> same;         // per tile: every value equals the reference's
};

// Row y's texels [x0, x1) of one tile, `kChannels` values a texel.
template <int kChannels, bool kReference>
void PredictRow(const Grid& g, const std::uint32_t* cur, const std::uint32_t* below,
                const std::uint32_t* prior, std::uint32_t x0, std::uint32_t x1,
                std::uint32_t* zg, std::uint32_t* zm, std::uint32_t* zt, std::uint64_t cost[3],
                unsigned char* same) {
    std::uint64_t cg = 0, cm = 0, ct = 0;
    unsigned char all_same = 1;
    for (std::uint64_t i = std::uint64_t{x0} * kChannels; i < std::uint64_t{x1} * kChannels; ++i) {
        const bool left = i >= kChannels;
        const std::uint64_t a = left ? cur[i - kChannels] : 0;
        const std::uint64_t b = below[i];
        const std::uint64_t d = left ? below[i - kChannels] : 0;
        const std::uint32_t value = cur[i];
        const std::uint32_t g1 = ZigZag(value, detail::Gradient(a, b, d, g.mask), g);
        const std::uint32_t m1 = ZigZag(value, detail::Med(a, b, d, g.mask), g);
        zg[i] = g1;
        zm[i] = m1;
        cg += static_cast<std::uint64_t>(std::bit_width(g1));
        cm += static_cast<std::uint64_t>(std::bit_width(m1));
        if constexpr (kReference) {
            const std::uint32_t t1 = ZigZag(value, prior[i], g);
            zt[i] = t1;
            ct += static_cast<std::uint64_t>(std::bit_width(t1));
            all_same &= static_cast<unsigned char>(value == prior[i]);
        }
    }
    cost[0] += cg;
    cost[1] += cm;
    if constexpr (kReference) {
        cost[2] += ct;
        *same &= all_same;
    }
}

template <int kChannels, bool kReference>
void PredictAll(const CodedHeader& h, const Grid& g, const std::uint32_t* v,
                const std::uint32_t* ref, Residuals& r) {
    const std::uint32_t across = TilesAcross(h);
    const auto tile = static_cast<std::uint32_t>(h.tile);
    const std::uint64_t row = std::uint64_t{g.width} * kChannels;
    const std::vector<std::uint32_t> zeros(row, 0);
    std::uint64_t costs[3] = {0, 0, 0};
    for (std::uint32_t y = 0; y < g.height; ++y) {
        const std::uint64_t at = y * row;
        const std::uint32_t* below = y > 0 ? v + at - row : zeros.data();
        const std::uint64_t tile_row = std::uint64_t{y / tile} * across;
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const std::uint64_t t = tile_row + tx;
            costs[0] = costs[1] = costs[2] = 0;
            unsigned char same = 1;
            PredictRow<kChannels, kReference>(
                g, v + at, below, kReference ? ref + at : nullptr, tx * tile,
                std::min(g.width, (tx + 1) * tile), r.z[0] + at, r.z[1] + at,
                kReference ? r.z[2] + at : nullptr, costs, &same);
            r.cost[0][t] += costs[0];
            r.cost[1][t] += costs[1];
            if constexpr (kReference) {
                r.cost[2][t] += costs[2];
                r.same[t] &= same;
            }
        }
    }
}

Residuals Predicted(const CodedHeader& h, const Grid& g, const std::uint32_t* v,
                    const std::uint32_t* ref, std::vector<std::uint32_t> (&scratch)[3]) {
    Residuals r;
    const std::uint64_t count = h.texels() * g.channels;
    const std::uint64_t tiles = std::uint64_t{TilesAcross(h)} * TilesUp(h);
    const int modes = ref != nullptr ? 3 : 2;
    for (int m = 0; m < modes; ++m) {
        if (scratch[m].size() < count) scratch[m].resize(count);  // every value is written below
        r.z[m] = scratch[m].data();
        r.cost[m].assign(tiles, 0);
    }
    if (ref != nullptr) r.same.assign(tiles, 1);
    if (g.channels == 1) {
        ref != nullptr ? PredictAll<1, true>(h, g, v, ref, r) : PredictAll<1, false>(h, g, v, ref, r);
    } else {
        ref != nullptr ? PredictAll<2, true>(h, g, v, ref, r) : PredictAll<2, false>(h, g, v, ref, r);
    }
    return r;
}

TileMode ChooseMode(const Residuals& r, std::uint64_t t) {
    if (!r.same.empty() && r.same[t]) return TileMode::kCopy;
    TileMode best = TileMode::kGradient;
    for (TileMode m : {TileMode::kMed, TileMode::kTemporal}) {
        const auto i = static_cast<int>(m);
        if (r.z[i] && r.cost[i][t] < r.cost[static_cast<int>(best)][t]) best = m;
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
    const Residuals predicted = Predicted(h, g, v.data(), ref, context_->residuals);
    std::vector<TileMode> modes(out.tiles);
    std::uint64_t residuals = 0;
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const TileSpan s = detail::SpanOf(h, tx, ty);
            const TileMode m = ChooseMode(predicted, std::uint64_t{ty} * across + tx);
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
    for (std::uint64_t t = 0; t < out.tiles; ++t) p[t] = static_cast<unsigned char>(modes[t]);
    p += out.tiles;
    for (const Exception& e : exceptions) {
        for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(e.index >> (8 * i));
        for (int i = 0; i < 4; ++i) p[4 + i] = static_cast<unsigned char>(e.bits >> (8 * i));
        p += 8;
    }
    // The residuals in walk order, then split into byte planes (one plane at a time: a loop the
    // compiler vectorises).
    std::vector<std::uint32_t>& walk = context_->walk;
    if (walk.size() < residuals) walk.resize(residuals);
    std::uint64_t k = 0;
    for (std::uint32_t ty = 0; ty < up; ++ty) {
        for (std::uint32_t tx = 0; tx < across; ++tx) {
            const TileMode m = modes[std::uint64_t{ty} * across + tx];
            if (m == TileMode::kCopy) continue;
            const TileSpan s = detail::SpanOf(h, tx, ty);
            const std::uint32_t* zs = predicted.z[static_cast<int>(m)];
            const std::uint64_t span = std::uint64_t(s.x1 - s.x0) * g.channels;
            for (std::uint32_t y = s.y0; y < s.y1; ++y) {
                std::memcpy(walk.data() + k, zs + (std::uint64_t{y} * width + s.x0) * g.channels,
                            span * sizeof(std::uint32_t));
                k += span;
            }
        }
    }
    for (int b = 0; b < planes; ++b) {
        unsigned char* plane = p + b * residuals;
        const int shift = 8 * b;
        for (std::uint64_t i = 0; i < residuals; ++i) {
            plane[i] = static_cast<unsigned char>(walk[i] >> shift);
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
