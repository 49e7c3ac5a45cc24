// The nearest-first keys of the pixel estimate's screen cells (depth_keys.h).
#include "depth_keys.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>

namespace lixel::scheduling {

float FloatAtOrBelow(double x) {
    constexpr float kLargest = std::numeric_limits<float>::max();
    constexpr float kInfinity = std::numeric_limits<float>::infinity();
    if (x >= kLargest) return kLargest;
    if (x < -static_cast<double>(kLargest)) return -kInfinity;
    const float f = static_cast<float>(x);  // the nearest float: at most one step above x
    return static_cast<double>(f) > x ? std::nextafter(f, -kInfinity) : f;
}

// A least-significant-digit radix sort on the keys' bits, flipped so that their unsigned order
// is the floats' (four passes of a byte; std::sort of the 10 000-box room's keys cost its plan
// 0.84 M instructions more).
std::vector<std::uint32_t> Ascending(const std::vector<float>& keys) {
    const std::size_t n = keys.size();
    std::vector<std::uint32_t> bits(n), order(n), next(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto u = std::bit_cast<std::uint32_t>(keys[i]);
        bits[i] = (u >> 31) != 0 ? ~u : u | 0x80000000u;
        order[i] = static_cast<std::uint32_t>(i);
    }
    for (int shift = 0; shift < 32; shift += 8) {
        std::array<std::size_t, 257> start{};
        for (std::size_t i = 0; i < n; ++i) ++start[((bits[i] >> shift) & 0xffu) + 1];
        for (int b = 0; b < 256; ++b) start[b + 1] += start[b];
        for (const std::uint32_t i : order) next[start[(bits[i] >> shift) & 0xffu]++] = i;
        order.swap(next);
    }
    return order;
}

}  // namespace lixel::scheduling
