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

// The value at (x, y, c) predicted by `mode` from already decoded values (`v`: left, below and
// below-left; texels outside the image are not read: the bottom row predicts from its left
// neighbour, the left column from the texel below, texel (0, 0) from 0) or from the reference
// `ref` (temporal modes). All arithmetic is modulo 2^N.
inline std::uint32_t Predict(TileMode mode, const Grid& g, const std::uint32_t* v,
                             const std::uint32_t* ref, std::uint32_t x, std::uint32_t y, int c) {
    const std::uint64_t at = (std::uint64_t{y} * g.width + x) * g.channels + c;
    if (mode == TileMode::kTemporal || mode == TileMode::kCopy) return ref[at];
    const std::uint64_t row = std::uint64_t{g.width} * g.channels;
    if (y == 0) return x == 0 ? 0u : v[at - g.channels];
    if (x == 0) return v[at - row];
    const std::uint64_t a = v[at - g.channels];
    const std::uint64_t b = v[at - row];
    const std::uint64_t d = v[at - row - g.channels];
    if (mode == TileMode::kMed) {
        const std::uint64_t lo = a < b ? a : b;
        const std::uint64_t hi = a < b ? b : a;
        if (d >= hi) return static_cast<std::uint32_t>(lo);
        if (d <= lo) return static_cast<std::uint32_t>(hi);
    }
    return static_cast<std::uint32_t>((a + b - d) & g.mask);
}

// (value - prediction) mod 2^N as a signed number in [-2^(N-1), 2^(N-1)), zig-zagged: 0, -1, 1,
// -2, ... become 0, 1, 2, 3, ...
inline std::uint32_t ZigZag(std::uint32_t value, std::uint32_t prediction, const Grid& g) {
    const std::uint64_t r = (std::uint64_t{value} - prediction) & g.mask;
    const std::uint64_t half = (g.mask >> 1) + 1;
    if (r < half) return static_cast<std::uint32_t>(2 * r);
    const std::uint64_t negative = g.mask + 1 - r;  // |s|, in [1, half]
    return static_cast<std::uint32_t>(2 * negative - 1);
}

inline std::uint32_t UnZigZag(std::uint32_t z, std::uint32_t prediction, const Grid& g) {
    const std::uint64_t s = (z & 1u) ? (g.mask + 1 - ((std::uint64_t{z} + 1) >> 1)) : (z >> 1);
    return static_cast<std::uint32_t>((prediction + s) & g.mask);
}

// The texels of tile (tx, ty): [x0, x1) x [y0, y1).
struct TileSpan {
    std::uint32_t x0, x1, y0, y1;
};
TileSpan SpanOf(const CodedHeader& h, std::uint32_t tx, std::uint32_t ty);

}  // namespace lixel::codec::detail
