// The coded map's header: fixed layout, little-endian, CRC-32 (zlib's) over its first 76 bytes.
#include <lixel/codec/coded_map.h>
#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <string>

namespace lixel::codec {

namespace {

constexpr unsigned char kMagic[4] = {'L', 'X', 'M', 'C'};
constexpr std::size_t kCrcOffset = 76;

void Put(unsigned char* out, std::uint64_t value, int bytes) {
    for (int i = 0; i < bytes; ++i) out[i] = static_cast<unsigned char>(value >> (8 * i));
}

std::uint64_t Get(const unsigned char* in, int bytes) {
    std::uint64_t value = 0;
    for (int i = 0; i < bytes; ++i) value |= std::uint64_t{in[i]} << (8 * i);
    return value;
}

std::uint32_t Crc32(const unsigned char* data, std::size_t size) {
    return static_cast<std::uint32_t>(crc32(crc32(0L, Z_NULL, 0), data, static_cast<uInt>(size)));
}

Error Bad(const std::string& field, const std::string& reason) {
    return Error{"coded_map." + field, reason};
}

}  // namespace

double QuantisedErrorBound(int bits, int shift) {
    const double steps = std::ldexp(1.0, bits) - 1.0;
    return std::ldexp(0.5, shift) / steps + std::ldexp(1.0, -25);
}

int BytePlanes(int bits) { return (bits + 7) / 8; }

std::uint32_t TilesAcross(const CodedHeader& h) {
    return (h.width + static_cast<std::uint32_t>(h.tile) - 1) / static_cast<std::uint32_t>(h.tile);
}

std::uint32_t TilesUp(const CodedHeader& h) {
    return (h.height + static_cast<std::uint32_t>(h.tile) - 1) / static_cast<std::uint32_t>(h.tile);
}

void WriteHeader(const CodedHeader& h, unsigned char out[kHeaderBytes]) {
    std::memset(out, 0, kHeaderBytes);
    std::memcpy(out, kMagic, 4);
    out[4] = kFormatVersion;
    out[5] = static_cast<unsigned char>(h.content);
    out[6] = static_cast<unsigned char>(h.codec);
    out[7] = static_cast<unsigned char>(h.bits);
    Put(out + 8, h.width, 4);
    Put(out + 12, h.height, 4);
    Put(out + 16, static_cast<std::uint64_t>(h.tile), 2);
    out[18] = static_cast<unsigned char>(h.max_shift);
    // 19 reserved, zero
    Put(out + 20, h.exceptions, 4);
    Put(out + 24, std::bit_cast<std::uint64_t>(h.error_bound), 8);
    Put(out + 32, h.frame_id, 8);
    Put(out + 40, h.reference_id, 8);
    Put(out + 48, h.keyframe_id, 8);
    Put(out + 56, h.payload_bytes, 8);
    Put(out + 64, h.raw_bytes, 8);
    // 72..75 reserved, zero
    Put(out + kCrcOffset, Crc32(out, kCrcOffset), 4);
}

Result<CodedHeader> ReadHeader(std::string_view bytes) {
    if (bytes.size() < kHeaderBytes) {
        return Bad("header", std::to_string(bytes.size()) + " bytes, shorter than the " +
                                 std::to_string(kHeaderBytes) + "-byte header");
    }
    const auto* in = reinterpret_cast<const unsigned char*>(bytes.data());
    if (std::memcmp(in, kMagic, 4) != 0) return Bad("magic", "not \"LXMC\": not a coded map");
    if (in[4] != kFormatVersion) {
        return Bad("version", std::to_string(in[4]) + ", this decoder reads version " +
                                  std::to_string(kFormatVersion));
    }
    if (Get(in + kCrcOffset, 4) != Crc32(in, kCrcOffset)) {
        return Bad("header", "CRC-32 mismatch: the header is corrupt");
    }
    CodedHeader h;
    if (in[5] != 1 && in[5] != 2) return Bad("content", std::to_string(in[5]) + " is not 1 or 2");
    h.content = static_cast<Content>(in[5]);
    if (in[6] != 1 && in[6] != 2) return Bad("codec", std::to_string(in[6]) + " is not 1 or 2");
    h.codec = static_cast<Codec>(in[6]);
    h.bits = in[7];
    if (h.codec == Codec::kQuantised) {
        if (h.content != Content::kDepth) return Bad("codec", "quantised codes depth only");
        if (h.bits < kMinQuantisedBits || h.bits > kMaxQuantisedBits) {
            return Bad("bits", std::to_string(h.bits) + " is outside [16, 24]");
        }
    } else if (h.bits != 32) {
        return Bad("bits", std::to_string(h.bits) + ": the exact codec has 32");
    }
    h.width = static_cast<std::uint32_t>(Get(in + 8, 4));
    h.height = static_cast<std::uint32_t>(Get(in + 12, 4));
    if (h.width < 1 || h.width > kMaxSide)
        return Bad("width", std::to_string(h.width) + " is outside [1, 16385]");
    if (h.height < 1 || h.height > kMaxSide)
        return Bad("height", std::to_string(h.height) + " is outside [1, 16385]");
    h.tile = static_cast<int>(Get(in + 16, 2));
    if (h.tile < kMinTile || h.tile > kMaxTile) {
        return Bad("tile", std::to_string(h.tile) + " is outside [8, 1024]");
    }
    h.max_shift = in[18];
    if (h.max_shift > (h.codec == Codec::kQuantised ? kMaxTileShift : 0)) {
        return Bad("max_shift", std::to_string(h.max_shift) + " is outside [0, " +
                                    (h.codec == Codec::kQuantised ? "8" : "0: the exact codec") +
                                    "]");
    }
    if (in[19] != 0 || Get(in + 72, 4) != 0) {
        return Bad("reserved", "bytes 19 and 72-75 must be zero");
    }
    h.exceptions = static_cast<std::uint32_t>(Get(in + 20, 4));
    if (h.exceptions > h.texels()) {
        return Bad("exceptions", std::to_string(h.exceptions) + ", more than the " +
                                     std::to_string(h.texels()) + " texels");
    }
    if (h.codec == Codec::kExact && h.exceptions != 0) {
        return Bad("exceptions", "the exact codec has none");
    }
    h.error_bound = std::bit_cast<double>(Get(in + 24, 8));
    const double bound =
        h.codec == Codec::kQuantised ? QuantisedErrorBound(h.bits, h.max_shift) : 0.0;
    // Bit for bit: -0 is not the exact codec's 0, nor a NaN any bound.
    if (std::bit_cast<std::uint64_t>(h.error_bound) != std::bit_cast<std::uint64_t>(bound)) {
        return Bad("error_bound", "not the bound its N and max_shift state");
    }
    h.frame_id = Get(in + 32, 8);
    h.reference_id = Get(in + 40, 8);
    h.keyframe_id = Get(in + 48, 8);
    if (h.frame_id == 0) return Bad("frame_id", "0 names no frame");
    if (h.reference_id == 0 && h.keyframe_id != h.frame_id) {
        return Bad("keyframe_id", "a keyframe (no reference) is its own keyframe");
    }
    if (h.reference_id != 0 && h.keyframe_id == 0) {
        return Bad("keyframe_id", "0: a frame with a reference names the keyframe it starts at");
    }
    if (h.reference_id != 0 && h.reference_id == h.frame_id) {
        return Bad("reference_id", "the frame's own id: a frame refers to another frame");
    }
    h.payload_bytes = Get(in + 56, 8);
    h.raw_bytes = Get(in + 64, 8);
    if (h.payload_bytes != bytes.size() - kHeaderBytes) {
        return Bad("payload_bytes", std::to_string(h.payload_bytes) + " stated, " +
                                        std::to_string(bytes.size() - kHeaderBytes) +
                                        " follow the header (truncated or padded)");
    }
    // The largest payload the header allows: tile modes, exceptions, every residual.
    const std::uint64_t tiles = std::uint64_t{TilesAcross(h)} * TilesUp(h);
    const std::uint64_t most =
        tiles + 8ull * h.exceptions + std::uint64_t(BytePlanes(h.bits)) * h.texels() * h.channels();
    if (h.raw_bytes < tiles || h.raw_bytes > most) {
        return Bad("raw_bytes", std::to_string(h.raw_bytes) + " is outside the [" +
                                    std::to_string(tiles) + ", " + std::to_string(most) +
                                    "] its size and tiles allow");
    }
    return h;
}

}  // namespace lixel::codec
