// The nearest-first keys of the pixel estimate's screen cells (depth_keys.h), against their
// definitions: a key is the largest float at or below its double, and the order is a stable
// sort of the keys.
#include "depth_keys.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

namespace lixel::scheduling {
namespace {

constexpr float kLargest = std::numeric_limits<float>::max();
constexpr float kInfinity = std::numeric_limits<float>::infinity();

// FloatAtOrBelow's definition, checked on its answer: at or below x, and the next float up
// (toward +infinity) above x, except that nothing above the largest finite float is answered.
void ExpectLargestAtOrBelow(double x) {
    const float f = FloatAtOrBelow(x);
    EXPECT_FALSE(std::isnan(f)) << x;
    EXPECT_LE(static_cast<double>(f), x) << x;
    EXPECT_NE(f, kInfinity) << x;
    if (f == kLargest) {
        EXPECT_GE(x, static_cast<double>(kLargest));
    } else {
        EXPECT_GT(static_cast<double>(std::nextafter(f, kInfinity)), x)
            << std::hexfloat << x << " gave " << f;
    }
}

TEST(FloatAtOrBelow, IsTheLargestFloatAtOrBelowItsDoubleOverEveryRange) {
    std::mt19937_64 rng(20261207);
    // Every bit pattern but NaNs: subnormals, both zeros, every exponent, infinities.
    for (int i = 0; i < 200000; ++i) {
        const double x = std::bit_cast<double>(rng());
        if (std::isnan(x)) continue;
        ExpectLargestAtOrBelow(x);
    }
    // Doubles near floats: a float and the doubles either side of it, where the nearest float
    // rounds up (the case the answer steps down from).
    std::uniform_int_distribution<std::uint32_t> float_bits(0, 0xffffffffu);
    for (int i = 0; i < 200000; ++i) {
        const float f = std::bit_cast<float>(float_bits(rng));
        if (!std::isfinite(f)) continue;
        const double d = f;
        for (const double x : {d, std::nextafter(d, -INFINITY), std::nextafter(d, INFINITY)}) {
            ExpectLargestAtOrBelow(x);
        }
    }
}

TEST(FloatAtOrBelow, KeysTheEdgesOfTheFloatsRangeByName) {
    const double largest = kLargest;
    const double past_largest = std::nextafter(largest, INFINITY);
    EXPECT_EQ(FloatAtOrBelow(largest), kLargest);
    // Past the range (a box 1e39 in front of the viewer), and a w that overflowed: the largest
    // float, never infinity, which could lie above the true, finite w.
    EXPECT_EQ(FloatAtOrBelow(past_largest), kLargest);
    EXPECT_EQ(FloatAtOrBelow(1e39), kLargest);
    EXPECT_EQ(FloatAtOrBelow(std::numeric_limits<double>::max()), kLargest);
    EXPECT_EQ(FloatAtOrBelow(INFINITY), kLargest);
    // Below the range nothing finite is at or below.
    EXPECT_EQ(FloatAtOrBelow(-largest), -kLargest);
    EXPECT_EQ(FloatAtOrBelow(-past_largest), -kInfinity);
    EXPECT_EQ(FloatAtOrBelow(-1e39), -kInfinity);
    EXPECT_EQ(FloatAtOrBelow(-INFINITY), -kInfinity);
    // Zeros keep their sign; the smallest positive double lies above 0 and below every positive
    // float; the smallest negative one below -0 and above the smallest negative float.
    EXPECT_TRUE(std::signbit(FloatAtOrBelow(-0.0)));
    EXPECT_FALSE(std::signbit(FloatAtOrBelow(0.0)));
    const double tiny = std::numeric_limits<double>::denorm_min();
    EXPECT_EQ(FloatAtOrBelow(tiny), 0.0f);
    EXPECT_EQ(FloatAtOrBelow(-tiny), -std::numeric_limits<float>::denorm_min());
    // 0.1 is no float: the nearest one lies above it, the answer one step below that.
    EXPECT_EQ(FloatAtOrBelow(0.1), std::nextafter(0.1f, 0.0f));
    EXPECT_EQ(FloatAtOrBelow(1.0), 1.0f);
}

// Ascending's reference: a stable sort of the indices by key, -0 before +0.
std::vector<std::uint32_t> StableOrder(const std::vector<float>& keys) {
    std::vector<std::uint32_t> order(keys.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        if (keys[a] != keys[b]) return keys[a] < keys[b];
        return std::signbit(keys[a]) && !std::signbit(keys[b]);
    });
    return order;
}

TEST(Ascending, EqualsAStableSortOfTheKeys) {
    std::mt19937 rng(29);
    // Few distinct keys (ties on every digit), both zeros and the infinities among them.
    const std::vector<float> few = {-kInfinity, -kLargest, -1.5f, -0.0f, 0.0f,
                                    std::numeric_limits<float>::denorm_min(), 2.0f, kInfinity};
    std::uniform_int_distribution<std::size_t> pick(0, few.size() - 1);
    std::uniform_int_distribution<std::uint32_t> float_bits(0, 0xffffffffu);
    for (const std::size_t n : {0u, 1u, 2u, 3u, 17u, 256u, 1000u, 70000u}) {
        for (int round = 0; round < 3; ++round) {
            std::vector<float> keys(n);
            for (float& k : keys) {
                if (round == 0) {
                    k = few[pick(rng)];
                } else {
                    do k = std::bit_cast<float>(float_bits(rng));
                    while (std::isnan(k));
                }
                // Round 2: many equal keys among the random ones.
                if (round == 2 && pick(rng) < 4) k = few[pick(rng)];
            }
            EXPECT_EQ(Ascending(keys), StableOrder(keys)) << n << " keys, round " << round;
        }
    }
}

}  // namespace
}  // namespace lixel::scheduling
