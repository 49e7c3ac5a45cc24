// fuzz_map_decode: lixel::codec's decoder on hostile coded maps (docs/service.md, "Coded maps").
// The first byte picks how the rest is used, so the fuzzer reaches past each check:
//   0: the bytes as a coded map, as they came;
//   1: the same with the header's CRC-32 made right (every header field's check);
//   2: a header built from the next bytes (small sizes; max_shift mostly the tiles' largest)
//      around the rest as the payload's content, compressed here with zstd's checksum on (tile
//      modes and shifts, exceptions, residuals), decoded with a reference of that shape held;
//   3: the rest as float32 texels, encoded (quantised tiles at shifts drawn from the texels'
//      bits) and decoded: integer values bit for bit, depth within the stated bound, the exact
//      codec bit for bit.
// Nothing may crash, leak or allocate past the decoder's budget; a decoded map has the texels
// its header states, and every value fits its N bits.
#include <fuzzer/FuzzedDataProvider.h>
#include <lixel/codec/map_decoder.h>
#include <lixel/codec/map_encoder.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace lixel::codec {
namespace {

constexpr std::uint64_t kBudget = 1u << 20;

void Require(bool holds, const char* what) {
    if (!holds) {
        std::fprintf(stderr, "fuzz_map_decode: %s\n", what);
        std::abort();
    }
}

void CheckDecoded(const Result<DecodedMap>& r) {
    if (!r) return;
    const CodedHeader& h = r->header;
    Require(r->texels.size() == h.texels() * h.channels(), "texel count is not the header's");
    Require(r->values.values.size() == r->texels.size(), "value count is not the texels'");
    const std::uint64_t mask = (std::uint64_t{1} << h.bits) - 1;
    for (std::uint32_t v : r->values.values) Require(v <= mask, "a value beyond N bits");
}

void FixCrc(std::string& bytes) {
    if (bytes.size() < kHeaderBytes) return;
    auto* p = reinterpret_cast<unsigned char*>(bytes.data());
    const auto crc = static_cast<std::uint32_t>(crc32(crc32(0L, Z_NULL, 0), p, 76));
    for (int i = 0; i < 4; ++i) p[76 + i] = static_cast<unsigned char>(crc >> (8 * i));
}

void Built(FuzzedDataProvider& in) {
    CodedHeader h;
    h.content = in.ConsumeBool() ? Content::kPoints : Content::kDepth;
    h.codec = h.content == Content::kPoints || in.ConsumeBool() ? Codec::kExact : Codec::kQuantised;
    h.bits = h.codec == Codec::kExact ? 32 : in.ConsumeIntegralInRange(16, 24);
    // Mostly the largest shift the tiles' bytes take (else the decoder stops at max_shift).
    const bool drawn_shift = in.ConsumeIntegralInRange(0, 7) == 0;
    h.max_shift = h.codec == Codec::kExact ? 0 : in.ConsumeIntegralInRange(0, kMaxTileShift);
    h.width = in.ConsumeIntegralInRange<std::uint32_t>(1, 40);
    h.height = in.ConsumeIntegralInRange<std::uint32_t>(1, 40);
    h.tile = in.ConsumeIntegralInRange(8, 24);
    h.exceptions = h.codec == Codec::kExact ? 0 : in.ConsumeIntegralInRange<std::uint32_t>(0, 4);
    h.frame_id = 2;
    const bool temporal = in.ConsumeBool();
    h.reference_id = temporal ? 1 : 0;
    h.keyframe_id = temporal ? 1 : 2;
    const std::string raw = in.ConsumeRemainingBytesAsString();
    if (h.codec == Codec::kQuantised && !drawn_shift) {
        const std::uint64_t tiles = std::uint64_t{TilesAcross(h)} * TilesUp(h);
        int largest = 0;
        for (std::uint64_t t = 0; t < tiles && t < raw.size(); ++t) {
            largest = std::max(largest, TileShift(static_cast<std::uint8_t>(raw[t])));
        }
        h.max_shift = std::min(largest, kMaxTileShift);
    }
    h.error_bound = h.codec == Codec::kExact ? 0.0 : QuantisedErrorBound(h.bits, h.max_shift);
    h.raw_bytes = raw.size();
    std::string packed(ZSTD_compressBound(raw.size()), '\0');
    ZSTD_CCtx* z = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(z, ZSTD_c_checksumFlag, 1);
    const std::size_t n = ZSTD_compress2(z, packed.data(), packed.size(), raw.data(), raw.size());
    ZSTD_freeCCtx(z);
    Require(!ZSTD_isError(n), "zstd failed on the harness's own input");
    packed.resize(n);
    h.payload_bytes = n;
    std::string bytes(kHeaderBytes, '\0');
    WriteHeader(h, reinterpret_cast<unsigned char*>(bytes.data()));
    bytes += packed;
    IntegerImage reference;
    reference.content = h.content;
    reference.codec = h.codec;
    reference.bits = h.bits;
    reference.width = h.width;
    reference.height = h.height;
    reference.frame_id = 1;
    reference.keyframe_id = 1;
    reference.values.assign(h.texels() * h.channels(),
                            0x5a5a5a5au & ((std::uint64_t{1} << h.bits) - 1));
    MapDecoder decoder(kBudget);
    CheckDecoded(decoder.Decode(bytes, {{1, &reference}}));
}

void RoundTrip(FuzzedDataProvider& in) {
    const bool points = in.ConsumeBool();
    const bool exact = points || in.ConsumeBool();
    const int bits = in.ConsumeIntegralInRange(16, 24);
    const std::uint32_t width = in.ConsumeIntegralInRange<std::uint32_t>(1, 64);
    const int channels = points ? 2 : 1;
    std::vector<float> texels;
    while (in.remaining_bytes() >= 4 && texels.size() < 64 * 64 * 2) {
        texels.push_back(std::bit_cast<float>(in.ConsumeIntegral<std::uint32_t>()));
    }
    const std::uint32_t height = static_cast<std::uint32_t>(texels.size() / (width * channels));
    if (height == 0) return;
    texels.resize(std::size_t{width} * height * channels);
    EncodeOptions o;
    o.codec = exact ? Codec::kExact : Codec::kQuantised;
    o.bits = bits;
    o.tile = 8;
    if (!exact) {  // each tile a shift from the input
        const std::uint64_t tiles = std::uint64_t{(width + 7) / 8} * ((height + 7) / 8);
        for (std::uint64_t t = 0; t < tiles; ++t) {
            o.tile_shifts.push_back(static_cast<std::uint8_t>(
                texels.size() > t ? std::bit_cast<std::uint32_t>(texels[t]) % 9 : 0));
        }
    }
    MapEncoder encoder;
    auto coded = encoder.Encode(points ? Content::kPoints : Content::kDepth, texels.data(), width,
                                height, o);
    Require(coded.ok(), "a valid image was not encoded");
    MapDecoder decoder(kBudget);
    auto back = decoder.Decode(coded->bytes);
    Require(back.ok(), "an encoded image was not decoded");
    Require(back->values.values == coded->decoded.values, "values differ after the round trip");
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const float d = texels[i];
        const float e = back->texels[i];
        if (exact || !(d >= 0.0f && d <= 1.0f)) {
            Require(std::bit_cast<std::uint32_t>(e) == std::bit_cast<std::uint32_t>(d) ||
                        (!exact && d == 0.0f && e == 0.0f),
                    "an exact texel changed");
        } else {
            Require(std::abs(double(e) - double(d)) <= back->header.error_bound,
                    "a quantised texel beyond the stated bound");
        }
    }
}

}  // namespace
}  // namespace lixel::codec

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace lixel::codec;
    if (size == 0) return 0;
    FuzzedDataProvider in(data + 1, size - 1);
    switch (data[0] % 4) {
        case 0:
        case 1: {
            std::string bytes(reinterpret_cast<const char*>(data + 1), size - 1);
            if (data[0] % 4 == 1) FixCrc(bytes);
            MapDecoder decoder(kBudget);
            CheckDecoded(decoder.Decode(bytes));
            break;
        }
        case 2:
            Built(in);
            break;
        default:
            RoundTrip(in);
            break;
    }
    return 0;
}
