// Render's coded maps.
#include <lixel/kit/shadow_block.h>
#include <lixel/service/map_coding.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lixel::service {

namespace {

Error Bad(const std::string& field, const std::string& reason) { return Error{field, reason}; }

}  // namespace

v1::PassKind PassKindOf(Pass pass, bool corner_depth) {
    if (corner_depth) return v1::PASS_CORNER_DEPTH;
    switch (pass) {
        case Pass::kDepth:
            return v1::PASS_DEPTH;
        case Pass::kSecondDepth:
            return v1::PASS_SECOND_DEPTH;
        case Pass::kSilhouetteMap:
            return v1::PASS_SILHOUETTE_MAP;
    }
    return v1::PASS_DEPTH;
}

Result<std::optional<MapCodingRequest>> DecodeMapEncoding(const v1::MapEncoding& m,
                                                          const std::string& field) {
    if (!v1::MapCodec_IsValid(m.codec())) {
        return Bad(field + ".codec", std::to_string(m.codec()) + " is not a MapCodec");
    }
    if (m.codec() == v1::MAP_CODEC_RAW) {
        // Raw float32 takes no coding setting: one set is a client that meant to code.
        const std::pair<bool, const char*> settings[] = {
            {m.bits() != 0, "bits"},    {m.zstd_level() != 0, "zstd_level"},
            {m.tile() != 0, "tile"},    {m.reference_frames_size() != 0, "reference_frames"},
            {m.keyframe(), "keyframe"}, {m.keyframe_interval() != 0, "keyframe_interval"}};
        for (const auto& [set, name] : settings) {
            if (set) return Bad(field + "." + name, "set, but the codec is raw float32");
        }
        return std::optional<MapCodingRequest>{};
    }
    MapCodingRequest r;
    r.depth_codec =
        m.codec() == v1::MAP_CODEC_EXACT ? codec::Codec::kExact : codec::Codec::kQuantised;
    if (m.bits() != 0) {
        if (m.codec() == v1::MAP_CODEC_EXACT) {
            return Bad(field + ".bits", "the exact codec keeps all 32 bits; leave it 0");
        }
        if (m.bits() < codec::kMinQuantisedBits || m.bits() > codec::kMaxQuantisedBits) {
            return Bad(field + ".bits",
                       std::to_string(m.bits()) + " is outside [16, 24] (0: chosen per map)");
        }
        r.bits = static_cast<int>(m.bits());
    }
    if (m.zstd_level() != 0) {
        if (m.zstd_level() < 1 || m.zstd_level() > kMaxZstdLevel) {
            return Bad(field + ".zstd_level",
                       std::to_string(m.zstd_level()) + " is outside [1, 9]");
        }
        r.zstd_level = m.zstd_level();
    }
    if (m.tile() != 0) {
        if (m.tile() < codec::kMinTile || m.tile() > codec::kMaxTile) {
            return Bad(field + ".tile", std::to_string(m.tile()) + " is outside [8, 1024]");
        }
        r.tile = static_cast<int>(m.tile());
    }
    if (m.reference_frames_size() > codec::kMaxReferenceFrames) {
        return Bad(field + ".reference_frames",
                   std::to_string(m.reference_frames_size()) + " ids, at most 64");
    }
    r.references.assign(m.reference_frames().begin(), m.reference_frames().end());
    r.keyframe = m.keyframe();
    if (m.keyframe_interval() != 0) {
        if (m.keyframe_interval() > 3600) {
            return Bad(field + ".keyframe_interval",
                       std::to_string(m.keyframe_interval()) + " is outside [1, 3600]");
        }
        r.keyframe_interval = static_cast<int>(m.keyframe_interval());
    }
    return std::optional<MapCodingRequest>{std::move(r)};
}

DepthQuantisation DefaultDepthQuantisation(const render::FloatImage& image, const LightMap& map,
                                           const Vec3& origin, bool corner_depth, int tile) {
    const Mat4 lixel = kit::MakeRelativeMatrices(map, origin).lixel;
    const Mat4 inverse = lixel.inverse();
    const Vec4 z_row = lixel.row(2).cwiseAbs().transpose();
    const Vec4 w_row = lixel.row(3).cwiseAbs().transpose();
    const double offset = corner_depth ? 0.0 : 0.5;
    // A side the encoder refuses (outside [8, 1024]) still divides nothing by zero here.
    tile = std::clamp(tile, codec::kMinTile, codec::kMaxTile);
    const int stride_x = std::max(1, std::min(image.width / 64, tile / 8));
    const int stride_y = std::max(1, std::min(image.height / 64, tile / 8));
    const int across = (image.width + tile - 1) / tile;
    const int up = (image.height + tile - 1) / tile;
    // The least rounding sampled in each tile, and over the image.
    std::vector<double> tile_least(static_cast<std::size_t>(across) * up,
                                   std::numeric_limits<double>::infinity());
    double least = std::numeric_limits<double>::infinity();
    for (int y = 0; y < image.height; y += stride_y) {
        for (int x = 0; x < image.width; x += stride_x) {
            const double d = image.at(x, y);
            if (!(d > 0.0 && d <= 1.0)) continue;  // cleared (0) is coded exactly
            // lixel_stored_depth_rounding (kit/glsl/lixel_shadows.glsl) at the texel's point p,
            // in double. With v = (x, y, d, 1) and h = inverse v, p = h_xyz / h_w and lixel p =
            // v / h_w: the kit's (|z_row|.|p| + d |w_row|.|p|) / |(lixel p)_w| is
            // (|z_row| + d |w_row|).|h|, one product and no division.
            const Vec4 h = inverse * Vec4(x + offset, y + offset, d, 1.0);
            if (!(std::abs(h.w()) > 0.0)) continue;  // a point at infinity has no rounding
            const double rounding = 0.5 * 1.1920929e-7 * (z_row + d * w_row).dot(h.cwiseAbs());
            if (!std::isfinite(rounding)) continue;
            least = std::min(least, rounding);
            double& in_tile = tile_least[static_cast<std::size_t>(y / tile) * across + x / tile];
            in_tile = std::min(in_tile, rounding);
        }
    }
    DepthQuantisation q;
    if (!std::isfinite(least)) {  // nothing drawn: all exact
        q.bits = codec::kMinQuantisedBits;
        return q;
    }
    // The room: a quarter of the bias, 16 x rounding.
    for (int bits = codec::kMinQuantisedBits; bits <= codec::kMaxQuantisedBits && q.bits == 0;
         ++bits) {
        if (codec::QuantisedErrorBound(bits) <= 4.0 * least) q.bits = bits;
    }
    if (q.bits == 0) return q;
    q.tile_shifts.resize(tile_least.size());
    for (std::size_t t = 0; t < tile_least.size(); ++t) {
        // A tile with no drawn sample may still hold drawn texels between the samples: it keeps
        // N's own step.
        int shift = 0;
        while (std::isfinite(tile_least[t]) && shift < codec::kMaxTileShift &&
               codec::QuantisedErrorBound(q.bits, shift + 1) <= 4.0 * tile_least[t]) {
            ++shift;
        }
        q.tile_shifts[t] = static_cast<std::uint8_t>(shift);
    }
    return q;
}

Result<std::string> MapCoder::Code(const LightMap& map, v1::PassKind kind,
                                   const render::FloatImage& image) {
    const bool points = kind == v1::PASS_SILHOUETTE_MAP;
    codec::EncodeOptions o;
    // A session's view mask is a lit fraction, not a depth: no bias absorbs its rounding, so it
    // goes lossless, as the silhouette points do.
    o.codec = points || kind == v1::PASS_MASK ? codec::Codec::kExact : request_.depth_codec;
    if (o.codec == codec::Codec::kQuantised) {
        if (request_.bits != 0) {
            o.bits = request_.bits;
        } else {
            DepthQuantisation q = DefaultDepthQuantisation(
                image, map, origin_, kind == v1::PASS_CORNER_DEPTH, request_.tile);
            o.bits = q.bits;
            o.tile_shifts = std::move(q.tile_shifts);
        }
        if (o.bits == 0) o.codec = codec::Codec::kExact;
    }
    o.zstd_level = request_.zstd_level;
    o.tile = request_.tile;
    o.frame_id = NewFrameId();
    ReferenceKey key{map.matrix, map.width, map.height, static_cast<int>(kind)};
    std::shared_ptr<const CodedReference> held;
    if (!request_.keyframe) held = references_.Find(request_.references, key);
    if (held && held->chain + 1 < request_.keyframe_interval) o.reference = held->values.get();
    const codec::Content content = points ? codec::Content::kPoints : codec::Content::kDepth;
    const auto width = static_cast<std::uint32_t>(image.width);
    const auto height = static_cast<std::uint32_t>(image.height);
    auto coded = encoder_.Encode(content, image.pixels.data(), width, height, o);
    if (!coded) return coded.error();
    // Many exceptions (texels outside [0, 1]) can make the quantised coding larger than a
    // client's bound on a coded image; the exact codec always fits it.
    if (coded->bytes.size() > codec::MaxCodedBytes(image.pixels.size() * sizeof(float)) &&
        o.codec == codec::Codec::kQuantised) {
        o.codec = codec::Codec::kExact;
        o.tile_shifts.clear();
        coded = encoder_.Encode(content, image.pixels.data(), width, height, o);
        if (!coded) return coded.error();
    }
    auto next = std::make_shared<CodedReference>();
    next->key = key;
    next->chain = coded->header.reference_id != 0 ? held->chain + 1 : 0;
    next->values = std::make_shared<codec::IntegerImage>(std::move(coded->decoded));
    references_.Put(std::move(next));
    return std::move(coded->bytes);
}

}  // namespace lixel::service
