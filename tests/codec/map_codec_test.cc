// lixel::codec (MapEncoder, MapDecoder): seeded round trips for every N and codec, the stated
// error bound on every texel, temporal tiles against a reference, and refusals of corrupt,
// truncated, padded and mismatched input.
#include <gtest/gtest.h>
#include <lixel/codec/map_decoder.h>
#include <lixel/codec/map_encoder.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <random>

namespace lixel::codec {
namespace {

// A depth image as a pass renders one: planar facets (depth affine in the texel), the clear
// value 0 where nothing was drawn, the near end 1, and a few values the quantiser cannot hold.
std::vector<float> DepthImage(std::mt19937_64& rng, std::uint32_t w, std::uint32_t h,
                              bool specials) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<float> out(std::size_t{w} * h);
    const int facets = 1 + static_cast<int>(u(rng) * 6);
    struct Facet {
        double a, b, c, x0, y0, r;
    };
    std::vector<Facet> f;
    for (int i = 0; i < facets; ++i) {
        f.push_back({(u(rng) - 0.5) * 1e-3, (u(rng) - 0.5) * 1e-3, u(rng), u(rng) * w, u(rng) * h,
                     u(rng) * std::max(w, h)});
    }
    for (std::uint32_t y = 0; y < h; ++y) {
        for (std::uint32_t x = 0; x < w; ++x) {
            float d = 0.0f;  // cleared
            for (const Facet& t : f) {
                if (std::hypot(x - t.x0, y - t.y0) < t.r) {
                    d = static_cast<float>(std::clamp(t.a * x + t.b * y + t.c, 0.0, 1.0));
                }
            }
            out[std::size_t{y} * w + x] = d;
        }
    }
    if (specials) {
        const float odd[] = {1.0f,
                             0.0f,
                             -0.25f,
                             1.5f,
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             std::numeric_limits<float>::quiet_NaN(),
                             1.0000001f,
                             -1e-30f,
                             std::numeric_limits<float>::denorm_min()};
        for (float v : odd) out[rng() % out.size()] = v;
    }
    return out;
}

std::uint32_t Bits(float f) { return std::bit_cast<std::uint32_t>(f); }

EncodeOptions Quantised(int bits, std::uint64_t frame, int tile = 64) {
    EncodeOptions o;
    o.codec = Codec::kQuantised;
    o.bits = bits;
    o.frame_id = frame;
    o.tile = tile;
    return o;
}

TEST(MapCodec, QuantisedRoundTripIsBitExactAndWithinTheBoundForEveryN) {
    std::mt19937_64 rng(12351);
    MapEncoder encoder;
    MapDecoder decoder;
    const std::uint32_t sizes[][2] = {{1, 1}, {1, 37}, {37, 1}, {64, 64}, {65, 63}, {200, 129}};
    for (int round = 0; round < 6; ++round) {
        for (int bits = kMinQuantisedBits; bits <= kMaxQuantisedBits; ++bits) {
            const auto [w, h] = sizes[(round + bits) % 6];
            const std::vector<float> depth = DepthImage(rng, w, h, w * h > 20);
            const int tile = round % 2 == 0 ? 64 : 8;
            auto coded =
                encoder.Encode(Content::kDepth, depth.data(), w, h, Quantised(bits, 7, tile));
            ASSERT_TRUE(coded) << coded.error().Message();
            auto back = decoder.Decode(coded->bytes);
            ASSERT_TRUE(back) << back.error().Message();
            EXPECT_EQ(back->values.values, coded->decoded.values) << "N = " << bits;
            const double bound = QuantisedErrorBound(bits);
            EXPECT_EQ(back->header.error_bound, bound);
            ASSERT_EQ(back->texels.size(), depth.size());
            for (std::size_t i = 0; i < depth.size(); ++i) {
                const float d = depth[i];
                const float e = back->texels[i];
                if (d >= 0.0f && d <= 1.0f) {
                    EXPECT_LE(std::abs(double(e) - double(d)), bound)
                        << "N = " << bits << " texel " << i;
                    if (d == 0.0f || d == 1.0f) {
                        EXPECT_EQ(e, d) << "texel " << i;
                    }
                } else {
                    EXPECT_EQ(Bits(e), Bits(d)) << "exception at texel " << i;
                }
            }
        }
    }
}

TEST(MapCodec, TheBoundIsTightAtItsWorstTexel) {
    // Midway between two steps the quantiser is off by half a step: the stated bound may exceed
    // that only by the float rounding of the decoded value.
    for (int bits = kMinQuantisedBits; bits <= kMaxQuantisedBits; ++bits) {
        const double steps = std::ldexp(1.0, bits) - 1.0;
        double worst = 0.0;
        std::vector<float> ramp(4096);
        for (std::size_t i = 0; i < ramp.size(); ++i) {
            ramp[i] =
                static_cast<float>((std::floor(0.3 * steps) + double(i) * 0.37 + 0.5) / steps);
        }
        MapEncoder encoder;
        MapDecoder decoder;
        auto coded = encoder.Encode(Content::kDepth, ramp.data(), 64, 64, Quantised(bits, 1));
        ASSERT_TRUE(coded);
        auto back = decoder.Decode(coded->bytes);
        ASSERT_TRUE(back);
        for (std::size_t i = 0; i < ramp.size(); ++i) {
            worst = std::max(worst, std::abs(double(back->texels[i]) - double(ramp[i])));
        }
        EXPECT_LE(worst, QuantisedErrorBound(bits));
        EXPECT_GE(worst, 0.45 / steps) << "N = " << bits;
    }
}

TEST(MapCodec, ExactCodecRestoresEveryBitOfDepthAndPoints) {
    std::mt19937_64 rng(777);
    MapEncoder encoder;
    MapDecoder decoder;
    for (int round = 0; round < 20; ++round) {
        const auto w = static_cast<std::uint32_t>(1 + rng() % 150);
        const auto h = static_cast<std::uint32_t>(1 + rng() % 90);
        const Content content = round % 2 == 0 ? Content::kDepth : Content::kPoints;
        const int channels = content == Content::kPoints ? 2 : 1;
        std::vector<float> texels(std::size_t{w} * h * channels);
        for (std::size_t i = 0; i < texels.size(); ++i) {
            // Mostly the empty (-1, -1) or smooth values, some arbitrary bit patterns (NaNs with
            // payloads, -0, infinities, denormals).
            const auto kind = rng() % 8;
            texels[i] = kind < 4   ? -1.0f
                        : kind < 7 ? static_cast<float>(i % 97) / 97.0f
                                   : std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
        }
        EncodeOptions o;
        o.codec = Codec::kExact;
        o.frame_id = 1 + round;
        o.tile = 8 << (round % 4);
        auto coded = encoder.Encode(content, texels.data(), w, h, o);
        ASSERT_TRUE(coded) << coded.error().Message();
        auto back = decoder.Decode(coded->bytes);
        ASSERT_TRUE(back) << back.error().Message();
        ASSERT_EQ(back->texels.size(), texels.size());
        EXPECT_EQ(std::memcmp(back->texels.data(), texels.data(), texels.size() * 4), 0);
        EXPECT_EQ(back->header.error_bound, 0.0);
    }
}

TEST(MapCodec, PlanarDepthCodesToAFewBitsPerTexel) {
    // Depth is affine in the texel on a planar facet, where the gradient predictor leaves only
    // the quantiser's rounding: a 512² plane at N = 24 takes well under 4 of 32 bits a texel.
    std::vector<float> plane(512 * 512);
    for (int y = 0; y < 512; ++y) {
        for (int x = 0; x < 512; ++x)
            plane[y * 512 + x] = static_cast<float>(0.2 + 3.1e-4 * x + 1.7e-4 * y);
    }
    MapEncoder encoder;
    auto coded = encoder.Encode(Content::kDepth, plane.data(), 512, 512, Quantised(24, 3));
    ASSERT_TRUE(coded);
    EXPECT_LT(static_cast<double>(coded->bytes.size()) * 8.0 / static_cast<double>(plane.size()),
              4.0)
        << coded->bytes.size() << " bytes";
}

TEST(MapCodec, TemporalTilesDecodeAgainstTheReferenceAndUnchangedTilesCostNothing) {
    std::mt19937_64 rng(4242);
    MapEncoder encoder;
    MapDecoder decoder;
    for (Codec codec : {Codec::kQuantised, Codec::kExact}) {
        std::vector<float> first = DepthImage(rng, 256, 192, true);
        EncodeOptions o = Quantised(20, 100);
        o.codec = codec;
        auto key = encoder.Encode(Content::kDepth, first.data(), 256, 192, o);
        ASSERT_TRUE(key);
        EXPECT_EQ(key->header.reference_id, 0u);
        EXPECT_EQ(key->header.keyframe_id, 100u);
        auto key_back = decoder.Decode(key->bytes);
        ASSERT_TRUE(key_back);

        // The next frame: one corner moved, the rest as it was.
        std::vector<float> second = first;
        for (int y = 0; y < 40; ++y) {
            for (int x = 0; x < 50; ++x) second[y * 256 + x] = 0.5f + 0.001f * float(x);
        }
        o.frame_id = 101;
        o.reference = &key->decoded;
        auto next = encoder.Encode(Content::kDepth, second.data(), 256, 192, o);
        ASSERT_TRUE(next);
        EXPECT_EQ(next->header.reference_id, 100u);
        EXPECT_EQ(next->header.keyframe_id, 100u);
        EXPECT_GE(next->temporal_tiles, next->tiles - 1);
        EXPECT_LT(next->bytes.size() * 4, key->bytes.size());

        const std::map<std::uint64_t, const IntegerImage*> held{{100, &key_back->values}};
        auto back = decoder.Decode(next->bytes, held);
        ASSERT_TRUE(back) << back.error().Message();
        EXPECT_EQ(back->values.values, next->decoded.values);
        EXPECT_EQ(back->values.keyframe_id, 100u);

        // The same frame again: every tile a copy.
        o.frame_id = 102;
        o.reference = &next->decoded;
        auto still = encoder.Encode(Content::kDepth, second.data(), 256, 192, o);
        ASSERT_TRUE(still);
        EXPECT_EQ(still->temporal_tiles, still->tiles);
        EXPECT_LT(still->bytes.size(), 200u);
    }
}

TEST(MapCodec, AFrameWithoutItsReferenceOrWithAnotherShapeIsRefusedNamingIt) {
    std::mt19937_64 rng(99);
    MapEncoder encoder;
    MapDecoder decoder;
    std::vector<float> a = DepthImage(rng, 64, 64, false);
    auto key = encoder.Encode(Content::kDepth, a.data(), 64, 64, Quantised(24, 5));
    ASSERT_TRUE(key);
    EncodeOptions o = Quantised(24, 6);
    o.reference = &key->decoded;
    auto next = encoder.Encode(Content::kDepth, a.data(), 64, 64, o);
    ASSERT_TRUE(next);
    ASSERT_EQ(next->header.reference_id, 5u);

    auto missing = decoder.Decode(next->bytes);
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().field, "coded_map.reference_id");
    EXPECT_NE(missing.error().reason.find("not held"), std::string::npos);

    IntegerImage other = key->decoded;
    other.bits = 20;
    auto wrong_bits = decoder.Decode(next->bytes, {{5, &other}});
    ASSERT_FALSE(wrong_bits);
    EXPECT_EQ(wrong_bits.error().field, "coded_map.reference_id");
    other = key->decoded;
    other.values.pop_back();
    EXPECT_FALSE(decoder.Decode(next->bytes, {{5, &other}}));
    // A reference with values beyond N bits (not one a decoder made) is refused, not trusted.
    other = key->decoded;
    other.values[0] = 1u << 24;
    EXPECT_FALSE(decoder.Decode(next->bytes, {{5, &other}}));

    // An encoder given a reference of another shape codes a keyframe.
    std::vector<float> small(32 * 32, 0.5f);
    o.frame_id = 7;
    auto keyframe = encoder.Encode(Content::kDepth, small.data(), 32, 32, o);
    ASSERT_TRUE(keyframe);
    EXPECT_EQ(keyframe->header.reference_id, 0u);
    EXPECT_TRUE(decoder.Decode(keyframe->bytes));
}

TEST(MapCodec, EveryFlippedBitTruncationAndPaddingIsRefused) {
    std::mt19937_64 rng(31337);
    MapEncoder encoder;
    MapDecoder decoder;
    std::vector<float> d = DepthImage(rng, 96, 80, true);
    auto coded = encoder.Encode(Content::kDepth, d.data(), 96, 80, Quantised(18, 9, 16));
    ASSERT_TRUE(coded);
    const std::string good = coded->bytes;
    auto original = decoder.Decode(good);
    ASSERT_TRUE(original);
    // The header's CRC-32 and zstd's content checksum catch every flipped bit that changes a
    // value: a flip is refused, or (a bit zstd's decoder never reads) decodes the same texels.
    int refused = 0;
    for (std::size_t byte = 0; byte < good.size(); ++byte) {
        for (int bit = 0; bit < 8; ++bit) {
            std::string bad = good;
            bad[byte] = static_cast<char>(bad[byte] ^ (1 << bit));
            auto r = decoder.Decode(bad);
            if (!r) {
                ++refused;
                continue;
            }
            EXPECT_GE(byte, kHeaderBytes) << "a header bit went unnoticed";
            EXPECT_EQ(r->values.values, original->values.values)
                << "byte " << byte << " bit " << bit;
            EXPECT_EQ(std::memcmp(r->texels.data(), original->texels.data(), r->texels.size() * 4),
                      0);
        }
    }
    EXPECT_GT(refused, static_cast<int>(good.size() * 8 * 95 / 100));
    for (std::size_t n = 0; n < good.size(); ++n) {
        EXPECT_FALSE(decoder.Decode(std::string_view(good).substr(0, n))) << n << " bytes";
    }
    auto padded = decoder.Decode(good + std::string(3, '\0'));
    ASSERT_FALSE(padded);
    EXPECT_EQ(padded.error().field, "coded_map.payload_bytes");
    auto none = decoder.Decode("");
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().field, "coded_map.header");
    auto wrong = decoder.Decode(std::string(200, 'x'));
    ASSERT_FALSE(wrong);
    EXPECT_EQ(wrong.error().field, "coded_map.magic");
}

TEST(MapCodec, SizesAreRefusedBeforeAnyAllocation) {
    // A header (with a valid CRC) that claims a 16385² image: refused by the decoder's texel
    // budget before the payload is read; one whose raw size exceeds what its shape allows is
    // refused by ReadHeader.
    CodedHeader h;
    h.codec = Codec::kQuantised;
    h.bits = 16;
    h.width = 16385;
    h.height = 16385;
    h.error_bound = QuantisedErrorBound(16);
    h.frame_id = h.keyframe_id = 1;
    h.raw_bytes = 1000000;
    h.payload_bytes = 10;
    std::string bytes(kHeaderBytes + 10, '\0');
    WriteHeader(h, reinterpret_cast<unsigned char*>(bytes.data()));
    MapDecoder small(1 << 20);
    auto big = small.Decode(bytes);
    ASSERT_FALSE(big);
    EXPECT_EQ(big.error().field, "coded_map.width");

    h.width = h.height = 4;
    h.raw_bytes = 1ull << 40;
    WriteHeader(h, reinterpret_cast<unsigned char*>(bytes.data()));
    auto raw = small.Decode(bytes);
    ASSERT_FALSE(raw);
    EXPECT_EQ(raw.error().field, "coded_map.raw_bytes");

    h.raw_bytes = 1 + 2 * 16;
    h.error_bound = 1e-3;  // not the bound N = 16 states
    WriteHeader(h, reinterpret_cast<unsigned char*>(bytes.data()));
    auto bound = small.Decode(bytes);
    ASSERT_FALSE(bound);
    EXPECT_EQ(bound.error().field, "coded_map.error_bound");
}

TEST(MapCodec, TheEncoderRefusesBadOptionsNamingThem) {
    MapEncoder encoder;
    std::vector<float> d(16, 0.5f);
    const auto field = [&](Content c, EncodeOptions o, std::uint32_t w = 4) {
        auto r = encoder.Encode(c, d.data(), w, 16 / std::max(w, 1u), o);
        return r ? std::string("ok") : r.error().field;
    };
    EXPECT_EQ(field(Content::kDepth, Quantised(15, 1)), "codec.bits");
    EXPECT_EQ(field(Content::kDepth, Quantised(25, 1)), "codec.bits");
    EXPECT_EQ(field(Content::kDepth, Quantised(16, 0)), "codec.frame_id");
    EXPECT_EQ(field(Content::kDepth, Quantised(16, 1, 7)), "codec.tile");
    EXPECT_EQ(field(Content::kDepth, Quantised(16, 1, 2048)), "codec.tile");
    EXPECT_EQ(field(Content::kPoints, Quantised(16, 1)), "codec.codec");
    EncodeOptions level = Quantised(16, 1);
    level.zstd_level = 0;
    EXPECT_EQ(field(Content::kDepth, level), "codec.zstd_level");
    EXPECT_EQ(field(Content::kDepth, Quantised(16, 1), 0), "codec.size");
    EXPECT_EQ(field(Content::kDepth, Quantised(16, 1)), "ok");
    EncodeOptions shifts = Quantised(16, 1, 8);  // a 4 x 4 image: one tile
    shifts.tile_shifts = {9};
    EXPECT_EQ(field(Content::kDepth, shifts), "codec.tile_shifts");
    shifts.tile_shifts = {1, 1};
    EXPECT_EQ(field(Content::kDepth, shifts), "codec.tile_shifts");
    shifts.tile_shifts = {1};
    EXPECT_EQ(field(Content::kDepth, shifts), "ok");
    shifts.codec = Codec::kExact;
    EXPECT_EQ(field(Content::kDepth, shifts), "codec.tile_shifts");
}

// Seeded shifts, a third of the tiles 0 (N's own step), the rest 1 to 8.
std::vector<std::uint8_t> SeededShifts(std::mt19937_64& rng, std::uint32_t w, std::uint32_t h,
                                       int tile) {
    std::vector<std::uint8_t> shifts(std::uint64_t{(w + tile - 1) / tile} *
                                     ((h + tile - 1) / tile));
    for (auto& s : shifts) s = rng() % 3 == 0 ? 0 : static_cast<std::uint8_t>(1 + rng() % 8);
    return shifts;
}

TEST(MapCodec, ShiftedTilesDecodeBitExactWithinTheirOwnBound) {
    // Every texel of a tile of shift s within QuantisedErrorBound(N, s) of its float, a multiple
    // of 2^s (or 2^N - 1: d = 1 stays exact), 0 and 1 exact, exceptions bit for bit; keyframes
    // and frames against them, the reference's tiles at other shifts.
    std::mt19937_64 rng(90125);
    MapEncoder encoder;
    MapDecoder decoder;
    for (int round = 0; round < 18; ++round) {
        const int bits = kMinQuantisedBits + round % 9;
        const int tile = round % 3 == 0 ? 64 : 8;
        const auto w = static_cast<std::uint32_t>(1 + rng() % 140);
        const auto h = static_cast<std::uint32_t>(1 + rng() % 90);
        std::vector<float> depth = DepthImage(rng, w, h, w * h > 20);
        std::optional<IntegerImage> held;
        for (int frame = 0; frame < 2; ++frame) {
            EncodeOptions o = Quantised(bits, 40 + frame, tile);
            o.tile_shifts = SeededShifts(rng, w, h, tile);
            if (held) o.reference = &*held;
            auto coded = encoder.Encode(Content::kDepth, depth.data(), w, h, o);
            ASSERT_TRUE(coded) << coded.error().Message();
            std::map<std::uint64_t, const IntegerImage*> refs;
            if (held) refs[held->frame_id] = &*held;
            auto back = decoder.Decode(coded->bytes, refs);
            ASSERT_TRUE(back) << back.error().Message();
            EXPECT_EQ(back->values.values, coded->decoded.values) << "N = " << bits;
            const int most = *std::max_element(o.tile_shifts.begin(), o.tile_shifts.end());
            EXPECT_EQ(back->header.max_shift, most);
            EXPECT_EQ(back->header.error_bound, QuantisedErrorBound(bits, most));
            const std::uint32_t mask = (1u << bits) - 1;
            for (std::uint32_t y = 0; y < h; ++y) {
                for (std::uint32_t x = 0; x < w; ++x) {
                    const std::size_t i = std::size_t{y} * w + x;
                    const int shift =
                        o.tile_shifts[(y / tile) * ((w + tile - 1) / tile) + x / tile];
                    const float d = depth[i];
                    const float e = back->texels[i];
                    if (!(d >= 0.0f && d <= 1.0f)) {
                        EXPECT_EQ(Bits(e), Bits(d)) << "exception at texel " << i;
                        continue;
                    }
                    EXPECT_LE(std::abs(double(e) - double(d)), QuantisedErrorBound(bits, shift))
                        << "N = " << bits << ", shift " << shift << ", texel " << i;
                    if (d == 0.0f || d == 1.0f) {
                        EXPECT_EQ(e, d) << "texel " << i;
                    }
                    const std::uint32_t q = back->values.values[i];
                    EXPECT_TRUE(q % (1u << shift) == 0 || q == mask) << "texel " << i;
                }
            }
            held = std::move(back->values);
            // The next frame: a few texels nudged by a step or two of N.
            for (std::size_t i = 0; i < depth.size(); i += 7) {
                if (depth[i] > 0.0f && depth[i] < 1.0f) {
                    depth[i] = static_cast<float>(std::clamp(
                        depth[i] + (int(rng() % 5) - 2) * std::ldexp(1.0, -bits), 0.0, 1.0));
                }
            }
        }
    }
}

TEST(MapCodec, AShiftedTileCostsFewerBytesOnRoughDepth) {
    // Depth the predictors leave ~12 bits a texel of at N = 24 (a plane plus noise of a few
    // thousand steps): each step of shift takes about a bit off every residual.
    std::mt19937_64 rng(4411);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::vector<float> rough(256 * 256);
    for (std::size_t i = 0; i < rough.size(); ++i) {
        rough[i] = static_cast<float>(0.3 + 1e-4 * double(i % 256) + 4e-4 * u(rng));
    }
    MapEncoder encoder;
    std::size_t previous = 0;
    for (int shift = 0; shift <= kMaxTileShift; shift += 4) {
        EncodeOptions o = Quantised(24, 1, 64);
        o.tile_shifts.assign(16, static_cast<std::uint8_t>(shift));
        auto coded = encoder.Encode(Content::kDepth, rough.data(), 256, 256, o);
        ASSERT_TRUE(coded);
        if (shift > 0) {
            EXPECT_LT(double(coded->bytes.size()), 0.8 * double(previous)) << "shift " << shift;
        }
        previous = coded->bytes.size();
    }
}

// A one-tile 8 x 8 map of N = 16: `tile_byte`, the first residual zig-zagged from `c`, the rest 0.
std::string OneTile(std::uint8_t tile_byte, std::uint32_t c, int max_shift,
                    Codec codec = Codec::kQuantised) {
    CodedHeader h;
    h.codec = codec;
    h.bits = codec == Codec::kExact ? 32 : 16;
    h.width = h.height = 8;
    h.tile = 8;
    h.max_shift = max_shift;
    h.error_bound = codec == Codec::kExact ? 0.0 : QuantisedErrorBound(16, max_shift);
    h.frame_id = h.keyframe_id = 5;
    const int planes = BytePlanes(h.bits);
    std::string raw(1 + 64 * planes, '\0');
    raw[0] = static_cast<char>(tile_byte);
    const std::uint32_t z = 2 * c;
    for (int b = 0; b < planes; ++b) raw[1 + b * 64] = static_cast<char>(z >> (8 * b));
    h.raw_bytes = raw.size();
    std::string packed(ZSTD_compressBound(raw.size()), '\0');
    ZSTD_CCtx* zc = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(zc, ZSTD_c_checksumFlag, 1);
    packed.resize(ZSTD_compress2(zc, packed.data(), packed.size(), raw.data(), raw.size()));
    ZSTD_freeCCtx(zc);
    h.payload_bytes = packed.size();
    std::string bytes(kHeaderBytes, '\0');
    WriteHeader(h, reinterpret_cast<unsigned char*>(bytes.data()));
    return bytes + packed;
}

TEST(MapCodec, AShiftedTilePastItsLimitOrHeaderIsRefusedNamingIt) {
    MapDecoder decoder;
    const std::uint8_t gradient8 = TileByte(TileMode::kGradient, 8);
    // c = 2^(16 - 8) is d = 1, the top step clamped to 2^16 - 1.
    auto top = decoder.Decode(OneTile(gradient8, 256, 8));
    ASSERT_TRUE(top) << top.error().Message();
    EXPECT_EQ(top->values.values[0], 0xFFFFu);
    EXPECT_EQ(top->texels[0], 1.0f);
    const auto field = [&](const std::string& bytes) {
        auto r = decoder.Decode(bytes);
        return r ? std::string("ok") : r.error().field;
    };
    // One past it would decode to the same value: a second coding of one map.
    EXPECT_EQ(field(OneTile(gradient8, 257, 8)), "coded_map.payload");
    EXPECT_EQ(field(OneTile(TileByte(TileMode::kMed, 8), 257, 8)), "coded_map.payload");
    EXPECT_EQ(field(OneTile(TileByte(TileMode::kGradient, 3), 1, 2)), "coded_map.tile_modes");
    EXPECT_EQ(field(OneTile(gradient8, 1, 9)), "coded_map.max_shift");
    // A header stating more than its tiles' largest shift: a second coding of the same map.
    EXPECT_EQ(field(OneTile(TileByte(TileMode::kGradient, 2), 1, 3)), "coded_map.max_shift");
    EXPECT_EQ(field(OneTile(0, 1, 1, Codec::kExact)), "coded_map.max_shift");
    EXPECT_EQ(field(OneTile(0x34, 1, 3)), "coded_map.tile_modes");  // mode 4
}

}  // namespace
}  // namespace lixel::codec
