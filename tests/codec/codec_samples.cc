// lixel::codec (MapEncoder, MapDecoder) as the reference for other decoders: writes seeded coded
// maps, what the C++ decoder makes of them, and its verdict on every flipped bit and every
// truncation of a few, into a directory; tests/codec/python_decoder_test.py decodes the same
// bytes with client/python/lixel_maps and must agree bit for bit and refusal for refusal.
//
//   lixel_codec_samples <dir>
//
// <dir>/manifest.jsonl: one JSON object a line, one a case: {"case", "content", "codec", "bits",
// "tile", "width", "height", "frame_id", "reference" (the case whose decoded values its temporal
// tiles read, or null), "temporal_tiles", "tiles", "damaged" (whether verdict files exist)}.
// Per case K: case_K.lxmc (the coded bytes), case_K.f32 (the C++ decoder's texels, float32
// little-endian, row 0 the bottom row, channels interleaved), case_K.u32 (its integer values).
// For damaged cases, case_K.flips ("byte bit verdict" a line, every bit of the coded bytes) and
// case_K.cuts ("length verdict" a line, every prefix), the verdict being the refusal's field or
// "ok"; decoded with the case's reference held.
#include <lixel/codec/map_decoder.h>
#include <lixel/codec/map_encoder.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace {

using lixel::codec::Codec;
using lixel::codec::Content;
using lixel::codec::EncodedMap;
using lixel::codec::EncodeOptions;
using lixel::codec::IntegerImage;
using lixel::codec::MapDecoder;
using lixel::codec::MapEncoder;

static_assert(std::endian::native == std::endian::little, "the sample files are little-endian");

struct Image {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::vector<float> texels;  // row 0 at the bottom, channels interleaved
};

// Depth as a pass renders it: planar facets (affine in the texel, so the gradient predictor
// leaves only rounding), sharp steps between them, the clear value 0 around them, the near end
// 1, a rough patch (where MED and, in a later frame, the reference predict better than a plane)
// and, with `specials`, values the quantiser must keep as exceptions.
Image DepthScene(std::mt19937_64& rng, std::uint32_t w, std::uint32_t h, bool specials) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Image image{w, h, std::vector<float>(std::size_t{w} * h, 0.0f)};
    const auto at = [&](std::uint32_t x, std::uint32_t y) -> float& {
        return image.texels[std::size_t{y} * w + x];
    };
    for (int facet = 0; facet < 4; ++facet) {
        const double a = (u(rng) - 0.5) * 4e-3, b = (u(rng) - 0.5) * 4e-3, c = 0.2 + 0.6 * u(rng);
        const double cx = u(rng) * w, cy = u(rng) * h, r = (0.2 + 0.5 * u(rng)) * std::max(w, h);
        for (std::uint32_t y = 0; y < h; ++y) {
            for (std::uint32_t x = 0; x < w; ++x) {
                if (std::hypot(x - cx, y - cy) < r) {
                    at(x, y) =
                        static_cast<float>(std::clamp(a * (x - cx) + b * (y - cy) + c, 0.0, 1.0));
                }
            }
        }
    }
    // The near end: a band along the top, exactly 1.
    for (std::uint32_t y = h - h / 8; y < h; ++y) {
        for (std::uint32_t x = 0; x < w / 3; ++x) at(x, y) = 1.0f;
    }
    // A rough patch: a plane plus noise of a few hundred N = 24 steps.
    for (std::uint32_t y = h / 4; y < h / 2; ++y) {
        for (std::uint32_t x = w / 2; x < w - w / 8; ++x) {
            at(x, y) = static_cast<float>(0.4 + 1e-4 * x + (u(rng) - 0.5) * 3e-5);
        }
    }
    if (specials) {
        using limits = std::numeric_limits<float>;
        const float odd[] = {limits::quiet_NaN(),
                             -0.5f,
                             2.0f,
                             limits::infinity(),
                             -limits::infinity(),
                             -0.0f,
                             1.0000001f,
                             limits::denorm_min(),
                             -1e-30f};
        for (float v : odd) image.texels[rng() % image.texels.size()] = v;
    }
    return image;
}

// Silhouette points: (-1, -1) where none, else a point near the texel on a few edges.
Image PointScene(std::mt19937_64& rng, std::uint32_t w, std::uint32_t h) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Image image{w, h, std::vector<float>(std::size_t{w} * h * 2, -1.0f)};
    for (int edge = 0; edge < 3; ++edge) {
        const double x0 = u(rng) * w, y0 = u(rng) * h, angle = u(rng) * 6.283185307179586;
        for (double t = 0.0; t < std::max(w, h); t += 0.7) {
            const double x = x0 + t * std::cos(angle), y = y0 + t * std::sin(angle);
            if (x < 0.0 || y < 0.0 || x >= w || y >= h) continue;
            const std::size_t i = (std::size_t(y) * w + std::size_t(x)) * 2;
            image.texels[i] = static_cast<float>(x + 0.1 * u(rng));
            image.texels[i + 1] = static_cast<float>(y + 0.1 * u(rng));
        }
    }
    return image;
}

// The next frame: the rough patch nudged (the reference predicts it within a few steps, a plane
// does not), a corner redrawn, every other tile as it was.
Image NextFrame(std::mt19937_64& rng, const Image& previous, Codec codec, int bits) {
    Image next = previous;
    const std::uint32_t w = next.width, h = next.height;
    for (std::uint32_t y = h / 4; y < h / 2; ++y) {
        for (std::uint32_t x = w / 2; x < w - w / 8; ++x) {
            float& d = next.texels[std::size_t{y} * w + x];
            if (!(d > 0.0f && d < 1.0f)) continue;
            // -2 to 2 steps (ulps exact): residuals of either sign, wrapping modulo 2^N.
            const int steps = static_cast<int>(rng() % 5) - 2;
            if (codec == Codec::kExact) {
                d = std::bit_cast<float>(std::bit_cast<std::uint32_t>(d) +
                                         static_cast<std::uint32_t>(steps));
            } else {
                d = static_cast<float>(d + steps * std::ldexp(1.0, -bits));
            }
        }
    }
    for (std::uint32_t y = 0; y < h / 5; ++y) {
        for (std::uint32_t x = 0; x < w / 5; ++x) {
            next.texels[std::size_t{y} * w + x] = static_cast<float>(0.3 + 1e-3 * x + 2e-3 * y);
        }
    }
    return next;
}

// The points moved by a few ulps on one edge; the rest unchanged.
Image NextPoints(std::mt19937_64& rng, const Image& previous) {
    Image next = previous;
    for (std::size_t i = 0; i < next.texels.size() / 3; ++i) {
        float& p = next.texels[i];
        if (p >= 0.0f) {
            p = std::bit_cast<float>(std::bit_cast<std::uint32_t>(p) +
                                     static_cast<std::uint32_t>(rng() % 3));
        }
    }
    return next;
}

struct Case {
    Content content;
    EncodedMap coded;
    std::optional<int> reference;  // the case whose decoded values it was coded against
    bool damaged = false;
};

bool Write(const std::string& path, const void* data, std::size_t bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
    return static_cast<bool>(out);
}

std::string Verdict(MapDecoder& decoder, std::string_view bytes,
                    const std::map<std::uint64_t, const IntegerImage*>& held) {
    auto r = decoder.Decode(bytes, held);
    return r ? "ok" : r.error().field;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s <directory>\n", argv[0]);
        return 2;
    }
    const std::string dir = argv[1];
    std::mt19937_64 rng(12351);
    MapEncoder encoder;
    std::vector<Case> cases;
    std::uint64_t next_frame = 1000;
    // `shifted`: each tile a seeded shift in [0, 8], a third of them 0.
    const auto encode = [&](Content content, const Image& image, Codec codec, int bits, int tile,
                            std::optional<int> reference, bool damaged,
                            bool shifted = false) -> bool {
        EncodeOptions o;
        o.codec = codec;
        o.bits = bits;
        o.tile = tile;
        o.frame_id = next_frame++;
        if (shifted) {
            const std::uint64_t tiles =
                std::uint64_t{(image.width + tile - 1) / tile} * ((image.height + tile - 1) / tile);
            for (std::uint64_t t = 0; t < tiles; ++t) {
                o.tile_shifts.push_back(rng() % 3 == 0 ? 0 : std::uint8_t(1 + rng() % 8));
            }
        }
        if (reference) o.reference = &cases[std::size_t(*reference)].coded.decoded;
        auto coded = encoder.Encode(content, image.texels.data(), image.width, image.height, o);
        if (!coded) {
            std::fprintf(stderr, "case %zu: %s\n", cases.size(), coded.error().Message().c_str());
            return false;
        }
        if (reference && coded->temporal_tiles == 0) {
            std::fprintf(stderr, "case %zu: a temporal frame with no temporal tile\n",
                         cases.size());
            return false;
        }
        cases.push_back({content, std::move(*coded), reference, damaged});
        return true;
    };
    bool ok = true;
    // Quantised depth at several N and both tile sizes, sides not multiples of the tile.
    const struct {
        std::uint32_t w, h;
        int bits, tile;
        bool damaged;
    } quantised[] = {
        {1, 1, 16, 8, false},     {37, 5, 24, 8, true},      {130, 67, 19, 64, false},
        {300, 200, 16, 8, false}, {300, 200, 24, 64, false}, {130, 67, 24, 8, false},
        {64, 64, 19, 8, false},
    };
    for (const auto& q : quantised) {
        ok = ok && encode(Content::kDepth, DepthScene(rng, q.w, q.h, q.w * q.h > 20),
                          Codec::kQuantised, q.bits, q.tile, std::nullopt, q.damaged);
    }
    // Quantised depth with tiles of coarser steps (every shift, rough and planar tiles alike).
    for (const auto& q : {quantised[1], quantised[2], quantised[4], quantised[6]}) {
        ok = ok && encode(Content::kDepth, DepthScene(rng, q.w, q.h, true), Codec::kQuantised,
                          q.bits, q.tile, std::nullopt, q.damaged, true);
    }
    // Exact depth and silhouette points: every bit kept.
    ok = ok && encode(Content::kDepth, DepthScene(rng, 300, 200, true), Codec::kExact, 32, 64,
                      std::nullopt, false);
    ok = ok && encode(Content::kDepth, DepthScene(rng, 37, 5, true), Codec::kExact, 32, 8,
                      std::nullopt, false);
    ok = ok && encode(Content::kPoints, PointScene(rng, 130, 67), Codec::kExact, 32, 8,
                      std::nullopt, false);
    ok = ok && encode(Content::kPoints, PointScene(rng, 33, 20), Codec::kExact, 32, 8, std::nullopt,
                      true);
    // Temporal chains: a keyframe, a frame against it, a frame against that.
    for (const auto& [codec, bits, tile, w, h, shifted] :
         {std::tuple{Codec::kQuantised, 19, 8, 130u, 67u, false},
          std::tuple{Codec::kExact, 32, 64, 300u, 200u, false},
          std::tuple{Codec::kQuantised, 24, 8, 40u, 24u, false},
          std::tuple{Codec::kQuantised, 22, 8, 130u, 67u, true}}) {
        Image frame = DepthScene(rng, w, h, true);
        const bool small = w * h < 2000;
        ok = ok && encode(Content::kDepth, frame, codec, bits, tile, std::nullopt, false, shifted);
        for (int step = 0; step < 2 && ok; ++step) {
            frame = NextFrame(rng, frame, codec, bits);
            ok = encode(Content::kDepth, frame, codec, bits, tile, int(cases.size()) - 1,
                        small && step == 0, shifted);
        }
    }
    {
        const Image points = PointScene(rng, 90, 40);
        ok = ok && encode(Content::kPoints, points, Codec::kExact, 32, 8, std::nullopt, false);
        ok = ok && encode(Content::kPoints, NextPoints(rng, points), Codec::kExact, 32, 8,
                          int(cases.size()) - 1, false);
    }
    if (!ok) return 1;

    MapDecoder decoder;
    std::vector<lixel::codec::DecodedMap> decoded;
    std::ofstream manifest(dir + "/manifest.jsonl");
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const Case& c = cases[k];
        std::map<std::uint64_t, const IntegerImage*> held;
        if (c.reference) {
            const IntegerImage& r = decoded[std::size_t(*c.reference)].values;
            held[r.frame_id] = &r;
        }
        auto back = decoder.Decode(c.coded.bytes, held);
        if (!back) {
            std::fprintf(stderr, "case %zu: %s\n", k, back.error().Message().c_str());
            return 1;
        }
        if (back->values.values != c.coded.decoded.values) {
            std::fprintf(stderr, "case %zu: the decoder's values are not the encoder's\n", k);
            return 1;
        }
        const std::string stem = dir + "/case_" + std::to_string(k);
        ok = Write(stem + ".lxmc", c.coded.bytes.data(), c.coded.bytes.size()) &&
             Write(stem + ".f32", back->texels.data(), back->texels.size() * sizeof(float)) &&
             Write(stem + ".u32", back->values.values.data(),
                   back->values.values.size() * sizeof(std::uint32_t));
        if (!ok) {
            std::fprintf(stderr, "%s: cannot write\n", stem.c_str());
            return 1;
        }
        const auto& h = c.coded.header;
        manifest << "{\"case\": " << k << ", \"content\": \""
                 << (c.content == Content::kPoints ? "points" : "depth") << "\", \"codec\": \""
                 << (h.codec == Codec::kExact ? "exact" : "quantised") << "\", \"bits\": " << h.bits
                 << ", \"tile\": " << h.tile << ", \"width\": " << h.width
                 << ", \"height\": " << h.height << ", \"frame_id\": " << h.frame_id
                 << ", \"reference\": " << (c.reference ? std::to_string(*c.reference) : "null")
                 << ", \"temporal_tiles\": " << c.coded.temporal_tiles
                 << ", \"tiles\": " << c.coded.tiles
                 << ", \"damaged\": " << (c.damaged ? "true" : "false") << "}\n";
        if (c.damaged) {
            std::ofstream flips(stem + ".flips");
            std::string bad = c.coded.bytes;
            for (std::size_t byte = 0; byte < bad.size(); ++byte) {
                for (int bit = 0; bit < 8; ++bit) {
                    bad[byte] = static_cast<char>(bad[byte] ^ (1 << bit));
                    flips << byte << ' ' << bit << ' ' << Verdict(decoder, bad, held) << '\n';
                    bad[byte] = c.coded.bytes[byte];
                }
            }
            std::ofstream cuts(stem + ".cuts");
            for (std::size_t n = 0; n <= c.coded.bytes.size(); ++n) {
                cuts << n << ' '
                     << Verdict(decoder, std::string_view(c.coded.bytes).substr(0, n), held)
                     << '\n';
            }
            ok = flips && cuts;
        }
        decoded.push_back(std::move(*back));
    }
    manifest.close();
    return ok && manifest ? 0 : 1;
}
