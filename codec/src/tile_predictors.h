// The predictors and the residual mapping the encoder and decoder share (docs/service.md,
// "Coded maps"): both walk the same texels in the same order and predict from the same decoded
// values, so a residual read back restores the value exactly.
#pragma once

#include <lixel/codec/coded_map.h>

#include <cstdint>

namespace lixel::codec::detail {

// The integer image's shape as the walk needs it.
struct Grid {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    int channels = 1;
    int bits = 24;
    std::uint64_t mask = 0;  // 2^N - 1
};

Grid GridOf(const CodedHeader& h);

// The spatial predictions from already decoded neighbours of the same channel: a left, b below,
// d below-left; texels outside the image read as 0, which is the format's edge rule (the bottom
// row predicts from its left neighbour, the left column from below, texel (0, 0) from 0). All
// arithmetic is modulo 2^N. Temporal tiles predict the reference's value at the same texel.
inline std::uint32_t Gradient(std::uint64_t a, std::uint64_t b, std::uint64_t d,
                              std::uint64_t mask) {
    return static_cast<std::uint32_t>((a + b - d) & mask);
}

// LOCO-I's median edge detector.
inline std::uint32_t Med(std::uint64_t a, std::uint64_t b, std::uint64_t d, std::uint64_t mask) {
    const std::uint64_t lo = a < b ? a : b;
    const std::uint64_t hi = a < b ? b : a;
    if (d >= hi) return static_cast<std::uint32_t>(lo);
    if (d <= lo) return static_cast<std::uint32_t>(hi);
    return static_cast<std::uint32_t>((a + b - d) & mask);
}

// A tile of shift s > 0 holds multiples of 2^s (its values q = min(c 2^s, 2^N - 1)) and codes
// each c: its predictors read every neighbour, in the tile or not, as Coarse(q, s), which gives
// back c inside the tile, and the predictions and residuals are those of the c's, modulo 2^N as
// everywhere. Shift 0 is the identity both ways.
inline std::uint32_t Coarse(std::uint32_t q, int shift) {
    return (q + ((1u << shift) >> 1)) >> shift;
}
inline std::uint32_t Fine(std::uint32_t c, int shift, std::uint32_t mask) {
    const std::uint32_t q = c << shift;
    return q < mask ? q : mask;
}
// Texels [x0, x0 + n) of a row read at shift s into `into`[1 .. n], `into`[0] the texel left of
// x0 (0 at the image's edge, the format's edge rule): the neighbours a shifted row's predictors
// read, in the encoder and the decoders alike. Every value is below 2^N <= 2^24 (an image's
// values, a checked reference's, the zero row), so the loop runs in signed 32-bit arithmetic,
// which SSE2 vectorises.
inline void CoarsenRow(const std::uint32_t* row, std::uint32_t x0, std::uint64_t n, int shift,
                       std::uint32_t* into) {
    into[0] = x0 > 0 ? Coarse(row[x0 - 1], shift) : 0;
    const std::int32_t half = (1 << shift) >> 1;
    const std::uint32_t* from = row + x0;
    for (std::uint64_t i = 0; i < n; ++i) {
        into[i + 1] =
            static_cast<std::uint32_t>((static_cast<std::int32_t>(from[i]) + half) >> shift);
    }
}

// The largest c a tile of shift s holds: 2^(N - s) (d = 1 rounds up to it, and Fine clamps it
// to 2^N - 1). A decoder refuses larger ones, which would give one map two codings.
inline std::uint32_t CoarseLimit(int bits, int shift) { return 1u << (bits - shift); }

// (value - prediction) mod 2^N as a signed number in [-2^(N-1), 2^(N-1)), zig-zagged: 0, -1, 1,
// -2, ... become 0, 1, 2, 3, ... Branch-free: residuals are noise around 0, so a branch on their
// sign would be mispredicted about half the time. 2^N divides 2^32, so uint32 arithmetic
// modulo 2^32 is arithmetic modulo 2^N before the mask.
inline std::uint32_t ZigZag(std::uint32_t value, std::uint32_t prediction, const Grid& g) {
    const int unused = 32 - g.bits;
    const auto r = static_cast<std::uint32_t>((value - prediction) << unused);
    const std::int32_t s = static_cast<std::int32_t>(r) >> unused;  // sign-extended from N bits
    return (static_cast<std::uint32_t>(s) << 1) ^ static_cast<std::uint32_t>(s >> 31);
}

inline std::uint32_t UnZigZag(std::uint32_t z, std::uint32_t prediction, const Grid& g) {
    const std::uint32_t s = (z >> 1) ^ (0u - (z & 1u));
    return static_cast<std::uint32_t>((prediction + s) & g.mask);
}

// The texels of tile (tx, ty): [x0, x1) x [y0, y1).
struct TileSpan {
    std::uint32_t x0, x1, y0, y1;
};
TileSpan SpanOf(const CodedHeader& h, std::uint32_t tx, std::uint32_t ty);

}  // namespace lixel::codec::detail
